// open_log(): the step-by-step reader hands out exactly the steps read_log()
// returns, for every format and rawlog layout; it reports damage when it gets
// there; and the rawlog's odometry source is decided as rawlog_collector.h
// says.
#include <gtest/gtest.h>

#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <cmath>

#include "hmt/io/carmen.h"
#include "hmt/io/log_reader.h"
#include "hmt/io/log_stream.h"
#include "hmt/io/rawlog.h"
#include "io_test_util.h"
#include "mrpt_test_util.h"

namespace hmt::io {
namespace {

using namespace testing_util;

void expect_same_steps(const hmt::Log& a, const hmt::Log& b) {
  EXPECT_EQ(a.source, b.source);
  ASSERT_EQ(a.steps.size(), b.steps.size());
  for (size_t k = 0; k < a.steps.size(); ++k) {
    const LogStep& x = a.steps[k];
    const LogStep& y = b.steps[k];
    SCOPED_TRACE("step " + std::to_string(k));
    EXPECT_EQ(x.timestamp, y.timestamp);
    EXPECT_EQ(x.has_odometry, y.has_odometry);
    EXPECT_EQ(x.odometry_increment.x, y.odometry_increment.x);
    EXPECT_EQ(x.odometry_increment.y, y.odometry_increment.y);
    EXPECT_EQ(x.odometry_increment.theta, y.odometry_increment.theta);
    EXPECT_EQ(x.scan.timestamp, y.scan.timestamp);
    EXPECT_EQ(x.scan.angle_min, y.scan.angle_min);
    EXPECT_EQ(x.scan.angle_increment, y.scan.angle_increment);
    EXPECT_EQ(x.scan.max_range, y.scan.max_range);
    EXPECT_EQ(x.scan.ranges, y.scan.ranges);
    EXPECT_EQ(x.scan.valid, y.scan.valid);
    EXPECT_EQ(x.scan.sensor_pose.x, y.scan.sensor_pose.x);
    EXPECT_EQ(x.scan.sensor_pose.theta, y.scan.sensor_pose.theta);
  }
}

// The steps as open_log() hands them out, one by one.
hmt::Log streamed(const std::string& path) {
  const std::unique_ptr<LogStream> s = open_log(path);
  hmt::Log log;
  log.source = s->source();
  LogStep step;
  while (s->next(step)) {
    log.steps.push_back(step);
    EXPECT_GE(s->fraction_read(), 0.0);
    EXPECT_LE(s->fraction_read(), 1.0);
  }
  EXPECT_EQ(s->fraction_read(), 1.0);
  EXPECT_FALSE(s->next(step));  // stays at the end
  return log;
}

TEST(LogStream, YieldsWhatReadLogReadsForEveryFormat) {
  const std::string dir = scratch_dir();
  const hmt::Log edmonton = read_carmen(edmonton_path());
  const std::string sf = dir + "/edmonton-sf.rawlog.gz";
  const std::string obs = dir + "/edmonton-obs.rawlog";
  write_rawlog(edmonton, sf, RawlogFormat::kActionsSensoryFrames);
  write_rawlog(edmonton, obs, RawlogFormat::kObservationsOnly);
  for (const std::string& path : {edmonton_path(), malaga_path(), sf, obs}) {
    SCOPED_TRACE(path);
    const hmt::Log whole = read_log(path);
    EXPECT_GT(whole.steps.size(), 100u);
    expect_same_steps(streamed(path), whole);
  }
  // The layouts agree with each other too (the steps the writer was given).
  EXPECT_EQ(read_log(obs).steps.size(), edmonton.steps.size());
  // A rawlog is read as it is taken, not whole up front.
  const std::unique_ptr<LogStream> s = open_log(obs);
  LogStep first;
  ASSERT_TRUE(s->next(first));
  EXPECT_LT(s->fraction_read(), 0.5);
  EXPECT_FALSE(s->total_steps());
  EXPECT_EQ(open_log(edmonton_path())->total_steps(), edmonton.steps.size());
}

TEST(LogStream, ObservationsOnlyWithScansBeforeTheFirstOdometry) {
  const std::string p = scratch_dir() + "/obs.rawlog";
  write_objects(p, {make_scan(0.8), make_scan(0.9),  // before any odometry
                    make_odometry(1.0, 10, 5, M_PI / 2), make_scan(1.1),
                    make_odometry(1.2, 10, 6, M_PI / 2), make_odometry(1.3, 10, 7, M_PI),
                    make_scan(1.4), make_scan(1.5), make_odometry(1.6, 11, 7, M_PI),
                    make_scan(1.7)});
  const hmt::Log log = streamed(p);
  expect_same_steps(log, read_log(p));
  ASSERT_EQ(log.steps.size(), 6u);
  EXPECT_FALSE(log.steps[0].has_odometry);
  // The scans before the first reading take it: no motion up to step 2.
  for (size_t k : {1u, 2u}) EXPECT_NEAR(log.steps[k].odometry_increment.norm(), 0.0, 1e-12);
  // 3: from (10,5,90deg) to (10,7,180deg): 2 m ahead, a quarter turn.
  EXPECT_NEAR(log.steps[3].odometry_increment.x, 2.0, 1e-9);
  EXPECT_NEAR(log.steps[3].odometry_increment.theta, M_PI / 2, 1e-9);
  EXPECT_NEAR(log.steps[4].odometry_increment.norm(), 0.0, 1e-12);
  // 5: 1 m along +x in the world while facing -x: 1 m backwards.
  EXPECT_NEAR(log.steps[5].odometry_increment.x, -1.0, 1e-9);
}

// Frames that also hold odometry readings: a movement before the second
// reading decides for movements, as reading the whole file did.
TEST(LogStream, FramesWithReadingsAndMovementsUseTheMovements) {
  const std::string p = scratch_dir() + "/sf-odo.rawlog";
  write_objects(p, {make_frame({make_odometry(1.0, 5, 5, 0), make_scan(1.0)}),
                    make_action(1.0, 0, 0),
                    make_frame({make_odometry(2.0, 50, 5, 0), make_scan(2.0)})});
  const hmt::Log log = streamed(p);
  expect_same_steps(log, read_log(p));
  ASSERT_EQ(log.steps.size(), 2u);
  EXPECT_NEAR(log.steps[1].odometry_increment.x, 1.0, 1e-9);  // the movement, not 45 m
}

TEST(LogStream, AMovementAfterTheReadingsWereChosenIsAnError) {
  const std::string p = scratch_dir() + "/mixed.rawlog";
  write_objects(p, {make_odometry(1.0, 0, 0, 0), make_scan(1.0), make_odometry(2.0, 1, 0, 0),
                    make_scan(2.0), make_action(1.0, 0, 0), make_frame({make_scan(3.0)})});
  expect_input_error([&] { streamed(p); },
                     {"mixed.rawlog", "entry 4", "CActionRobotMovement2D",
                      "must use one or the other"});
}

// A class only MRPT reads, after steps were handed out: the stream goes on
// from the plugin's log with the same steps.
TEST(LogStream, SwitchesToTheMrptPluginMidFile) {
  const std::string p = scratch_dir() + "/image.rawlog";
  write_objects(p, {make_odometry(1.0, 0, 0, 0), make_scan(1.0), make_odometry(2.0, 1, 0, 0),
                    make_scan(2.0), make_odometry(3.0, 2, 0, 0), make_scan(3.0),
                    mrpt::obs::CObservationImage::Create(), make_odometry(4.0, 3, 0, 0),
                    make_scan(4.0)});
  const hmt::Log log = streamed(p);
  expect_same_steps(log, read_log(p));
  ASSERT_EQ(log.steps.size(), 4u);
  EXPECT_NEAR(log.steps[3].odometry_increment.x, 1.0, 1e-9);
}

// Damage is found when the reader gets there: the steps before it are
// handed out, then the same error read_log() gives.
TEST(LogStream, TruncatedRawlogFailsWhereTheDamageIs) {
  const std::string dir = scratch_dir();
  const std::string whole = dir + "/whole.rawlog";
  write_rawlog(read_carmen(edmonton_path()), whole, RawlogFormat::kObservationsOnly);
  const std::string bytes = read_bytes(whole);
  const std::string cut = dir + "/cut.rawlog";
  write_bytes(cut, bytes.substr(0, bytes.size() * 2 / 3));
  const std::unique_ptr<LogStream> s = open_log(cut);
  size_t got = 0;
  LogStep step;
  try {
    while (s->next(step)) ++got;
    FAIL() << "a truncated rawlog read to its end";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("cut.rawlog"), std::string::npos) << what;
    EXPECT_NE(what.find("is truncated"), std::string::npos) << what;
  }
  EXPECT_GT(got, 100u);
  expect_input_error([&] { read_log(cut); }, {"cut.rawlog", "is truncated"});
}

TEST(LogStream, CarmenKnowsItsLengthAndReadsLinesLongerThanABuffer) {
  // 30 000 beams: a line of ~120 KB, longer than one read of the file; the
  // last line has no newline.
  std::string text = "PARAM robot_frontlaser_offset 0.1\n";
  for (int k = 0; k < 3; ++k) text += flaser(30000, "2.5", 0.1 * k, k);
  text.pop_back();
  const std::string p = scratch_dir() + "/long_lines.log";
  write_bytes(p, text);
  const auto stream = open_log(p);
  ASSERT_TRUE(stream->total_steps().has_value());
  EXPECT_EQ(*stream->total_steps(), 3u);
  EXPECT_EQ(stream->fraction_read(), 0.0);
  LogStep step;
  double last = 0.0;
  for (int k = 0; k < 3; ++k) {
    ASSERT_TRUE(stream->next(step));
    EXPECT_EQ(step.scan.ranges.size(), 30000u);
    EXPECT_FLOAT_EQ(step.scan.ranges.back(), 2.5f);
    EXPECT_DOUBLE_EQ(step.scan.sensor_pose.x, 0.1);
    EXPECT_DOUBLE_EQ(step.timestamp, k);
    EXPECT_GE(stream->fraction_read(), last);
    last = stream->fraction_read();
  }
  EXPECT_FALSE(stream->next(step));
  EXPECT_EQ(stream->fraction_read(), 1.0);
}

TEST(LogStream, CarmenDamageFailsBeforeAnyStep) {
  // Every line is parsed when the log is opened: a bad last line stops the
  // run before it starts, as the whole-file reader did.
  const std::string p = scratch_dir() + "/bad_last_line.log";
  write_bytes(p, flaser(5, "1.5", 0, 0) + flaser(5, "1.5", 0.1, 1) +
                     flaser(5, "nan", 0.2, 2));
  expect_input_error([&] { open_log(p); }, {p, "line 3", "range 0 is nan"});
}

TEST(LogStream, ACarmenLogChangedBetweenThePassesIsAnError) {
  const std::string p = scratch_dir() + "/changing.log";
  const std::string two = flaser(5, "1.5", 0, 0) + flaser(5, "1.5", 0.1, 1);
  for (const std::string& now : {two + flaser(5, "1.5", 0.2, 2), std::string(two, 0, two.size() / 2)}) {
    write_bytes(p, two);
    const auto stream = open_log(p);
    write_bytes(p, now);
    expect_input_error([&] { drain(*stream); }, {p, "changed while it was read"});
  }
}

TEST(LogStream, ACarmenLineLongerThan64MbIsAnError) {
  // A file without newlines is not a text log; reading it line by line
  // would hold it whole. (A real FLASER line of 100 000 beams is ~1 MB.)
  const std::string p = scratch_dir() + "/one_long_line.log";
  std::string text = "FLASER 3";
  text.resize((size_t{64} << 20) + 100, '1');
  write_bytes(p, text);
  expect_input_error([&] { open_log(p); }, {p, "line 1", "longer than 64 MB", "not a text log"});
}

}  // namespace
}  // namespace hmt::io

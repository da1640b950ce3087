// Writing a stream as a rawlog and reading it back must give the same stream.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "hmt/io/carmen.h"
#include "hmt/io/log_reader.h"
#include "hmt/io/rawlog.h"
#include "io_test_util.h"

namespace hmt::io {
namespace {

using namespace testing_util;

// Beam directions are compared in the robot frame: MRPT scans are symmetric
// about the sensor axis, so an asymmetric scan comes back with its bearings
// split differently between sensor_pose.theta and angle_min (see rawlog.h).
void expect_same_stream(const hmt::Log& a, const hmt::Log& b) {
  ASSERT_EQ(a.steps.size(), b.steps.size());
  for (size_t k = 0; k < a.steps.size(); ++k) {
    SCOPED_TRACE("step " + std::to_string(k));
    const LogStep& x = a.steps[k];
    const LogStep& y = b.steps[k];
    EXPECT_NEAR(x.timestamp, y.timestamp, 1e-6);
    EXPECT_NEAR(x.scan.timestamp, y.scan.timestamp, 1e-6);
    EXPECT_EQ(x.has_odometry, y.has_odometry);
    EXPECT_NEAR(x.odometry_increment.x, y.odometry_increment.x, 1e-6);
    EXPECT_NEAR(x.odometry_increment.y, y.odometry_increment.y, 1e-6);
    EXPECT_NEAR(wrap_angle(x.odometry_increment.theta -
                           y.odometry_increment.theta),
                0.0, 1e-6);
    ASSERT_EQ(x.scan.size(), y.scan.size());
    EXPECT_EQ(x.scan.ranges, y.scan.ranges);
    EXPECT_EQ(x.scan.valid, y.scan.valid);
    EXPECT_EQ(x.scan.max_range, y.scan.max_range);
    EXPECT_NEAR(x.scan.angle_increment, y.scan.angle_increment, 1e-6);
    EXPECT_NEAR(x.scan.sensor_pose.x, y.scan.sensor_pose.x, 1e-9);
    EXPECT_NEAR(x.scan.sensor_pose.y, y.scan.sensor_pose.y, 1e-9);
    for (size_t i : {size_t(0), x.scan.size() / 2, x.scan.size() - 1}) {
      const double dx = x.scan.sensor_pose.theta + x.scan.bearing(i);
      const double dy = y.scan.sensor_pose.theta + y.scan.bearing(i);
      EXPECT_NEAR(wrap_angle(dx - dy), 0.0, 1e-5) << "beam " << i;
    }
  }
}

class RoundTripConversion : public ::testing::TestWithParam<RawlogFormat> {};

TEST_P(RoundTripConversion, CarmenToRawlog) {
  const hmt::Log carmen = read_carmen(edmonton_path());
  const std::string dir = scratch_dir();
  for (const char* name : {"/edmonton.rawlog", "/edmonton.rawlog.gz"}) {
    SCOPED_TRACE(name);
    const std::string p = dir + name;
    write_rawlog(carmen, p, GetParam());
    const hmt::Log back = read_log(p);
    EXPECT_EQ(back.source, p);
    expect_same_stream(carmen, back);
  }
  // The .gz one is really compressed, the other is not.
  EXPECT_LT(std::filesystem::file_size(dir + "/edmonton.rawlog.gz") * 2,
            std::filesystem::file_size(dir + "/edmonton.rawlog"));
}

TEST_P(RoundTripConversion, MalagaRawlog) {
  const hmt::Log orig = read_rawlog(malaga_path());
  const std::string p = scratch_dir() + "/malaga.rawlog";
  write_rawlog(orig, p, GetParam());
  const hmt::Log back = read_rawlog(p);
  expect_same_stream(orig, back);
  // Symmetric scans come back field by field.
  for (size_t k = 0; k < orig.steps.size(); ++k) {
    EXPECT_EQ(orig.steps[k].scan.angle_min, back.steps[k].scan.angle_min);
    EXPECT_NEAR(orig.steps[k].scan.sensor_pose.theta,
                back.steps[k].scan.sensor_pose.theta, 1e-6);
  }
}

// Times before 1970 (some CARMEN logs start at t < 0) and odd geometry.
TEST_P(RoundTripConversion, NegativeTimesAndDescendingBeams) {
  hmt::Log log;
  for (int k = 0; k < 4; ++k) {
    LogStep s;
    s.timestamp = -1.5 + 0.4 * k;
    s.has_odometry = k > 0;
    if (k > 0) s.odometry_increment = Pose2D(0.3, -0.1, 3.0);
    s.scan.timestamp = s.timestamp;
    s.scan.angle_min = 1.0f;
    s.scan.angle_increment = -0.25f;  // left to right
    s.scan.max_range = 20.0f;
    s.scan.ranges = {1.0f, 2.5f, 20.0f, 3.0f};
    s.scan.valid = {1, 1, 0, 1};
    s.scan.sensor_pose = Pose2D(0.1, 0.2, 3.1);
    log.steps.push_back(s);
  }
  const std::string p = scratch_dir() + "/odd.rawlog";
  write_rawlog(log, p, GetParam());
  const hmt::Log back = read_rawlog(p);
  ASSERT_EQ(back.steps.size(), 4u);
  for (size_t k = 0; k < 4; ++k) {
    const LogStep& y = back.steps[k];
    EXPECT_NEAR(y.timestamp, log.steps[k].timestamp, 1e-6);
    // Read back ascending: the same beams in reverse order.
    EXPECT_EQ(y.scan.ranges, (std::vector<float>{3.0f, 20.0f, 2.5f, 1.0f}));
    EXPECT_EQ(y.scan.valid, (std::vector<uint8_t>{1, 0, 1, 1}));
    EXPECT_GT(y.scan.angle_increment, 0.0f);
    for (size_t i = 0; i < 4; ++i) {
      const double want = 3.1 + 1.0 - 0.25 * double(3 - i);
      EXPECT_NEAR(wrap_angle(y.scan.sensor_pose.theta + y.scan.bearing(i) -
                             want),
                  0.0, 1e-6);
    }
    if (k > 0) {
      EXPECT_NEAR(y.odometry_increment.x, 0.3, 1e-9);
      EXPECT_NEAR(y.odometry_increment.y, -0.1, 1e-9);
      EXPECT_NEAR(y.odometry_increment.theta, 3.0, 1e-9);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    BothFormats, RoundTripConversion,
    ::testing::Values(RawlogFormat::kActionsSensoryFrames,
                      RawlogFormat::kObservationsOnly),
    [](const ::testing::TestParamInfo<RawlogFormat>& info) {
      return info.param == RawlogFormat::kActionsSensoryFrames
                 ? std::string("ActionsSensoryFrames")
                 : std::string("ObservationsOnly");
    });

TEST(RawlogFileCreation, FailureLeavesNothingBehind) {
  const hmt::Log log = read_rawlog(malaga_path());
  const std::string p = scratch_dir() + "/missing_dir/out.rawlog";
  EXPECT_THROW(write_rawlog(log, p, RawlogFormat::kObservationsOnly),
               hmt::OutputError);
  EXPECT_FALSE(std::filesystem::exists(p));
}

TEST(RawlogFileCreation, UnrepresentableStepIsAnOutputError) {
  hmt::Log log;
  log.steps.resize(1);  // a scan without beams
  const std::string dir = scratch_dir();
  EXPECT_THROW(write_rawlog(log, dir + "/x.rawlog",
                            RawlogFormat::kActionsSensoryFrames),
               hmt::OutputError);
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

TEST(RawlogFileCreation, OverwritesAtomically) {
  const std::string p = scratch_dir() + "/out.rawlog";
  write_bytes(p, "old content");
  const hmt::Log log = read_carmen(edmonton_path());
  write_rawlog(log, p, RawlogFormat::kActionsSensoryFrames);
  EXPECT_EQ(read_rawlog(p).steps.size(), 340u);
}

}  // namespace
}  // namespace hmt::io

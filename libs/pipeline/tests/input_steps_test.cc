// The job's input read step by step: [input] selection on the fly, peeking,
// and the second reading for the keyframes' scans, which must find the log
// the run read.
#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "hmt/checkpoint/checkpoint.h"
#include "hmt/common/error.h"
#include "hmt/pipeline/input_steps.h"
#include "kept_steps.h"

namespace hmt::pipeline {
namespace {

// `n` steps `step` metres apart, step k at time k with the scan
// scan_at(k), the odometry saying so up to step `frozen_from` (exclusive)
// and nothing after it.
Log walk(const std::string& source, size_t n, double step, size_t frozen_from,
         const std::function<LaserScan(size_t)>& scan_at) {
  Log log;
  log.source = source;
  for (size_t k = 0; k < n; ++k) {
    LogStep s;
    s.timestamp = static_cast<double>(k);
    s.has_odometry = k > 0;
    if (k > 0 && k < frozen_from) s.odometry_increment = Pose2D(step, 0, 0);
    s.scan = scan_at(k);
    log.steps.push_back(s);
  }
  return log;
}

// `n` steps 0.5 m apart; step k's scan reads k metres.
Log straight_log(size_t n) {
  return walk("straight.log", n, 0.5, n, [](size_t k) {
    LaserScan scan;
    scan.ranges.assign(3, static_cast<float>(k));
    scan.valid.assign(3, 1);
    return scan;
  });
}

TEST(InputSteps, SelectsAsTheWholeLogSelectionDid) {
  InputOptions in;
  in.first_step = 2;
  in.max_steps = 5;
  InputSteps steps(io::stream_of(straight_log(10)), in);
  EXPECT_EQ(steps.total_steps(), 5u);
  ASSERT_NE(steps.peek(1), nullptr);
  EXPECT_EQ(steps.peek(1)->timestamp, 3.0);  // peeking takes nothing
  LogStep s;
  std::vector<double> times;
  while (steps.next(s)) times.push_back(s.timestamp);
  EXPECT_EQ(times, (std::vector<double>{2, 3, 4, 5, 6}));
  EXPECT_EQ(steps.taken(), 5u);
  EXPECT_EQ(steps.peek(), nullptr);
  const Log selected = in.select(straight_log(10));
  ASSERT_EQ(selected.steps.size(), 5u);
  EXPECT_EQ(selected.steps.front().timestamp, 2.0);
}

TEST(InputSteps, BrokenOdometryNamesTheStepOfTheLog) {
  Log log = straight_log(10);
  log.steps[6].odometry_increment = Pose2D(30, 0, 0);
  InputOptions in;
  in.first_step = 1;
  InputSteps steps(io::stream_of(log), in);
  LogStep s;
  try {
    while (steps.next(s)) {
    }
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("log 'straight.log' step 6: the odometry moves the robot 30 m"),
              std::string::npos) << what;
  }
}

// A room's scan of `beams` beams from a robot `x` metres along it: the
// ranges grow with x (a wall ahead moving away), so scans from two places a
// metre or more apart differ in every beam.
LaserScan room_scan(double x, size_t beams = 90) {
  LaserScan scan;
  scan.max_range = 30.0f;
  for (size_t i = 0; i < beams; ++i)
    scan.ranges.push_back(static_cast<float>(2.0 + 0.01 * static_cast<double>(i) + x));
  scan.valid.assign(beams, 1);
  return scan;
}

// Steps every `step` metres along the room by the scans, the odometry saying
// so up to step `frozen_from` (exclusive) and nothing after it.
Log walk(size_t n, double step, size_t frozen_from) {
  return walk("walk.log", n, step, frozen_from,
              [step](size_t k) { return room_scan(step * static_cast<double>(k)); });
}

std::string read_all(const Log& log) {
  InputSteps steps(io::stream_of(log), InputOptions{});
  LogStep s;
  try {
    while (steps.next(s)) {
    }
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(InputSteps, OdometryThatStandsStillWhileTheScansMoveIsAnError) {
  // Working odometry: every scan differs from the one before by a metre,
  // and no scan is compared across that motion.
  EXPECT_EQ(read_all(walk(12, 1.0, 12)), "");
  // Frozen from step 5 on: step 4 is the last place the odometry moves to,
  // and step 5's scene moved without it.
  const std::string what = read_all(walk(12, 1.0, 5));
  EXPECT_NE(what.find("log 'walk.log' step 5: 100 % of the laser's returns changed by more "
                      "than 0.5 m since step 4"),
            std::string::npos)
      << what;
  EXPECT_NE(what.find("the odometry is frozen or missing"), std::string::npos) << what;
  // No odometry at all: the second scan already gives it away.
  EXPECT_NE(read_all(walk(12, 1.0, 1)).find("step 1:"), std::string::npos);
}

TEST(InputSteps, ARobotStandingStillMaySeeItsSceneChangeInPart) {
  // Standing still for 20 steps while something near the laser (people, a
  // door) changes 70 % of the beams: the same place, not an error.
  Log log = walk(4, 1.0, 4);
  for (size_t k = 0; k < 20; ++k) {
    LogStep s;
    s.timestamp = static_cast<double>(log.steps.size());
    s.has_odometry = true;
    s.scan = log.steps.back().scan;
    for (size_t i = 0; i < s.scan.size() * 7 / 10; ++i) s.scan.ranges[i] = 0.6f + 0.01f * k;
    log.steps.push_back(s);
  }
  EXPECT_EQ(read_all(log), "");
  // With fewer beams returning in both than the check needs, it says nothing.
  Log sparse = walk(6, 1.0, 1);
  for (LogStep& s : sparse.steps) s.scan = room_scan(s.timestamp, 19);
  EXPECT_EQ(read_all(sparse), "");
}

TEST(InputSteps, CountsTimestampsThatDoNotIncrease) {
  Log log = straight_log(8);
  InputOptions in;
  in.first_step = 1;
  {
    InputSteps steps(io::stream_of(log), in);
    LogStep s;
    while (steps.next(s)) {
    }
    EXPECT_EQ(steps.clock_faults().count, 0u);
  }
  log.steps[3].timestamp = 2.0;  // repeats step 2's
  log.steps[6].timestamp = 4.5;  // before step 5's
  InputSteps steps(io::stream_of(log), in);
  LogStep s;
  while (steps.next(s)) {
  }
  const InputSteps::ClockFaults& c = steps.clock_faults();
  EXPECT_EQ(c.count, 2u);
  // Indices among the steps taken (the log's step 3 is the second).
  EXPECT_EQ(c.first_step, 2u);
  EXPECT_EQ(c.first_time, 2.0);
  EXPECT_EQ(c.time_before, 2.0);
}

uint32_t fingerprint(const Log& log) {
  uint32_t crc = 0;
  for (const LogStep& s : log.steps) crc = checkpoint::log_fingerprint(crc, s);
  return crc;
}

TEST(ReadStepsAgain, ReturnsTheWantedStepsWhole) {
  const Log log = straight_log(10);
  const LogOpener open = [&] { return io::stream_of(log); };
  // Steps numbered on from 100 (a resumed session).
  const auto got = read_steps_again(open, InputOptions(), 100, 10, fingerprint(log), {101, 107});
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got.at(107).scan.ranges, log.steps[7].scan.ranges);
  EXPECT_EQ(got.at(101).timestamp, 1.0);
}

TEST(ReadStepsAgain, ALogChangedSinceTheRunIsAnError) {
  const Log log = straight_log(10);
  Log changed = log;
  changed.steps[8].scan.ranges[1] = 42.0f;
  Log shorter = log;
  shorter.steps.resize(7);
  for (const Log* again : {&changed, &shorter}) {
    const LogOpener open = [&] { return io::stream_of(*again); };
    try {
      read_steps_again(open, InputOptions(), 0, 10, fingerprint(log), {3});
      FAIL() << "no error";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("the log 'straight.log' changed during the run"), std::string::npos)
          << what;
    }
  }
}

}  // namespace
}  // namespace hmt::pipeline

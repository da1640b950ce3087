// Reading MRPT rawlogs: the embedded Malaga log and hand-made files for the
// cases it does not cover (observations-only odometry, several scans per
// frame, left-to-right and upside-down scanners, gzip).
#include <gtest/gtest.h>

#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <cmath>

#include "hmt/io/log_reader.h"
#include "hmt/io/rawlog.h"
#include "io_test_util.h"
#include "mrpt_test_util.h"

namespace hmt::io {
namespace {

using namespace testing_util;

TEST(RawlogConversion, MalagaLog) {
  const hmt::Log log = read_rawlog(malaga_path());
  // 225 sensory frames with one scan each, and 224 odometry actions between
  // them (the first frame has no action before it).
  ASSERT_EQ(log.steps.size(), 225u);
  EXPECT_EQ(log.source, malaga_path());
  EXPECT_FALSE(log.steps[0].has_odometry);
  double path = 0.0, prev_t = 0.0;
  size_t invalid = 0;
  for (size_t k = 0; k < log.steps.size(); ++k) {
    const LogStep& s = log.steps[k];
    EXPECT_EQ(s.has_odometry, k > 0);
    EXPECT_LT(s.odometry_increment.norm(), 2.0) << "step " << k;
    EXPECT_LT(std::abs(s.odometry_increment.theta), 1.0) << "step " << k;
    path += s.odometry_increment.norm();
    ASSERT_EQ(s.scan.size(), 361u);
    ASSERT_EQ(s.scan.valid.size(), 361u);
    EXPECT_NEAR(s.scan.angle_min, -M_PI / 2, 1e-6);
    EXPECT_NEAR(s.scan.angle_increment, M_PI / 360, 1e-7);
    EXPECT_FLOAT_EQ(s.scan.max_range, 80.0f);
    EXPECT_NEAR(s.scan.sensor_pose.x, 0.78, 1e-7);  // stored as a float
    EXPECT_NEAR(s.scan.sensor_pose.y, 0.0, 1e-9);
    EXPECT_NEAR(s.scan.sensor_pose.theta, 0.0, 1e-9);
    EXPECT_EQ(s.timestamp, s.scan.timestamp);
    EXPECT_GT(s.timestamp, prev_t);
    prev_t = s.timestamp;
    for (size_t i = 0; i < s.scan.size(); ++i) {
      if (!s.scan.valid[i]) {
        ++invalid;
        // Malaga's no-returns are stored as ~81.9 m, above maxRange.
        EXPECT_GT(s.scan.ranges[i], 80.0f);
      } else {
        EXPECT_GT(s.scan.ranges[i], 0.0f);
        EXPECT_LT(s.scan.ranges[i], 80.0f);
      }
    }
  }
  EXPECT_EQ(invalid, 9312u);
  // January 2006, 59 s long.
  EXPECT_NEAR(log.steps.front().timestamp, 1137834225.713386, 1e-5);
  EXPECT_NEAR(log.steps.back().timestamp - log.steps.front().timestamp, 59.07,
              0.01);
  EXPECT_GT(path, 50.0);
  EXPECT_LT(path, 200.0);
}

TEST(RawlogConversion, ReadLogPicksTheRawlogReader) {
  EXPECT_EQ(detect_log_format(malaga_path()), LogFormat::kRawlog);
  EXPECT_EQ(read_log(malaga_path()).steps.size(), 225u);
}

TEST(RawlogConversion, PlainAndGzipRawlogsReadAlike) {
  const std::string p = scratch_dir() + "/malaga_plain.rawlog";
  write_bytes(p, gunzip_file(malaga_path()));
  const hmt::Log a = read_rawlog(malaga_path());
  const hmt::Log b = read_log(p);
  ASSERT_EQ(a.steps.size(), b.steps.size());
  for (size_t k = 0; k < a.steps.size(); ++k) {
    EXPECT_EQ(a.steps[k].scan.ranges, b.steps[k].scan.ranges);
    EXPECT_EQ(a.steps[k].odometry_increment.x, b.steps[k].odometry_increment.x);
  }
}

// Odometry observations: each scan takes the latest reading before it in
// the file; scans before the first reading take that first reading.
TEST(RawlogConversion, ObservationsOnlyOdometry) {
  const std::string p = scratch_dir() + "/obs.rawlog";
  auto img = mrpt::obs::CObservationImage::Create();  // skipped
  write_objects(p, {make_scan(0.9),  // before any odometry
                    make_odometry(1.0, 10, 5, M_PI / 2), make_scan(1.1),
                    make_odometry(1.2, 10, 6, M_PI / 2),
                    make_odometry(1.3, 10, 7, M_PI), img, make_scan(1.4),
                    make_scan(1.5)});
  const hmt::Log log = read_rawlog(p);
  ASSERT_EQ(log.steps.size(), 4u);
  EXPECT_FALSE(log.steps[0].has_odometry);
  EXPECT_NEAR(log.steps[0].timestamp, 0.9, 1e-6);
  // 1: same pose as the first reading.
  EXPECT_TRUE(log.steps[1].has_odometry);
  EXPECT_NEAR(log.steps[1].odometry_increment.norm(), 0.0, 1e-12);
  // 2: from (10,5,90deg) to (10,7,180deg): 2 m straight ahead, turn 90 deg.
  const Pose2D inc = log.steps[2].odometry_increment;
  EXPECT_NEAR(inc.x, 2.0, 1e-9);
  EXPECT_NEAR(inc.y, 0.0, 1e-9);
  EXPECT_NEAR(inc.theta, M_PI / 2, 1e-9);
  // 3: no new reading, no motion.
  EXPECT_TRUE(log.steps[3].has_odometry);
  EXPECT_NEAR(log.steps[3].odometry_increment.norm(), 0.0, 1e-12);
  EXPECT_NEAR(log.steps[3].timestamp, 1.5, 1e-6);
}

TEST(RawlogConversion, ActionsAndSensoryFrames) {
  const std::string p = scratch_dir() + "/sf.rawlog";
  write_objects(
      p, {make_frame({make_scan(1.0)}), make_action(1.0, 0, 0),
          make_action(1.0, 0, M_PI / 2),  // two actions compose
          make_frame({make_scan(2.0), make_scan(2.0)}),
          make_action(0.5, 0.1, 0.2, /*scan_matching=*/true),
          make_frame({mrpt::obs::CObservationImage::Create(), make_scan(3.0)})});
  const hmt::Log log = read_log(p);
  ASSERT_EQ(log.steps.size(), 4u);
  EXPECT_FALSE(log.steps[0].has_odometry);
  const Pose2D a = log.steps[1].odometry_increment;
  EXPECT_NEAR(a.x, 2.0, 1e-9);
  EXPECT_NEAR(a.y, 0.0, 1e-9);
  EXPECT_NEAR(a.theta, M_PI / 2, 1e-9);
  // Second scan of the same frame: no motion since the first.
  EXPECT_TRUE(log.steps[2].has_odometry);
  EXPECT_NEAR(log.steps[2].odometry_increment.norm(), 0.0, 1e-12);
  const Pose2D c = log.steps[3].odometry_increment;
  EXPECT_NEAR(c.x, 0.5, 1e-9);
  EXPECT_NEAR(c.y, 0.1, 1e-9);
  EXPECT_NEAR(c.theta, 0.2, 1e-9);
}

TEST(RawlogConversion, ScanConventions) {
  const std::string p = scratch_dir() + "/conv.rawlog";
  auto l2r = make_scan(2.0);  // readings 1..5 from left to right
  l2r->rightToLeft = false;
  auto flipped = make_scan(3.0);  // upside down: mirrored seen from above
  flipped->sensorPose = mrpt::poses::CPose3D(0.2, 0.1, 0.5, 0.3, 0, M_PI);
  auto odd = make_scan(4.0);
  odd->setScanRangeValidity(1, false);
  odd->setScanRange(2, 0.0f);                // zero: no return
  odd->setScanRange(3, 30.0f);               // at maxRange: no return
  odd->setScanRange(4, std::numeric_limits<float>::infinity());
  write_objects(p, {make_odometry(0, 0, 0, 0), make_scan(1.0), l2r, flipped,
                    odd});
  const hmt::Log log = read_rawlog(p);
  ASSERT_EQ(log.steps.size(), 4u);
  const std::vector<float> up{1, 2, 3, 4, 5}, down{5, 4, 3, 2, 1};
  EXPECT_EQ(log.steps[0].scan.ranges, up);
  EXPECT_EQ(log.steps[1].scan.ranges, down);
  EXPECT_EQ(log.steps[2].scan.ranges, down);
  for (const auto& s : log.steps) {
    EXPECT_NEAR(s.scan.angle_min, -M_PI / 2, 1e-6);
    EXPECT_NEAR(s.scan.angle_increment, M_PI / 4, 1e-6);
  }
  const Pose2D sp = log.steps[2].scan.sensor_pose;
  EXPECT_NEAR(sp.x, 0.2, 1e-12);
  EXPECT_NEAR(sp.y, 0.1, 1e-12);
  EXPECT_NEAR(sp.theta, 0.3, 1e-12);
  const LaserScan& o = log.steps[3].scan;
  EXPECT_EQ(o.valid, (std::vector<uint8_t>{1, 0, 0, 0, 0}));
  EXPECT_EQ(o.ranges[4], 30.0f);  // +inf stored as maxRange
  EXPECT_EQ(o.max_range, 30.0f);
}

}  // namespace
}  // namespace hmt::io

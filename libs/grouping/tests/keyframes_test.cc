#include "hmt/grouping/keyframes.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hmt::grouping {
namespace {

LaserScan scan_with_returns(size_t valid) {
  LaserScan s;
  s.angle_min = -M_PI / 2;
  s.angle_increment = M_PI / 180;
  s.max_range = 30.0f;
  s.ranges.assign(181, 5.0f);
  s.valid.assign(181, 0);
  for (size_t i = 0; i < valid && i < 181; ++i) s.valid[i] = 1;
  return s;
}

// Scans along x every 0.125 m (exact in binary), all with returns.
struct Fixture {
  Log log;
  ScanPoses poses;
  explicit Fixture(int n) {
    for (int i = 0; i < n; ++i) {
      LogStep s;
      s.timestamp = i;
      s.scan = scan_with_returns(181);
      log.steps.push_back(s);
      poses.pose.push_back(Pose2D(0.125 * i, 0.0, 0.0));
      poses.has_pose.push_back(1);
    }
  }
};

TEST(Keyframes, SpacedByDistance) {
  Fixture f(19);  // 0 .. 2.25 m
  const auto sel = select_keyframes(f.log, f.poses, 0.5, 1.0);
  ASSERT_EQ(sel.keyframes.size(), 5u);  // 0, 0.5, 1.0, 1.5, 2.0
  EXPECT_EQ(sel.keyframes[1].scan, 4);
  EXPECT_DOUBLE_EQ(sel.keyframes[1].timestamp, 4.0);
  EXPECT_DOUBLE_EQ(sel.keyframes[4].pose.x, 2.0);
}

TEST(Keyframes, TurningInPlaceMakesKeyframes) {
  Fixture f(10);
  for (int i = 0; i < 10; ++i) f.poses.pose[i] = Pose2D(0, 0, wrap_angle(0.2 * i));
  const auto sel = select_keyframes(f.log, f.poses, 0.5, 0.5);
  // 0, 0.6, 1.2, 1.8 (the angle since the last keyframe reaches 0.6 >= 0.5).
  ASSERT_EQ(sel.keyframes.size(), 4u);
  EXPECT_EQ(sel.keyframes[1].scan, 3);
}

TEST(Keyframes, ZeroThresholdsTakeEveryScanWithAPose) {
  Fixture f(6);
  f.poses.has_pose[2] = 0;
  const auto sel = select_keyframes(f.log, f.poses, 0.0, 0.0);
  ASSERT_EQ(sel.keyframes.size(), 5u);
  EXPECT_EQ(sel.keyframes[2].scan, 3);
}

TEST(Keyframes, ScansThatSenseTooLittleAreSkipped) {
  Fixture f(11);  // 0 .. 1.25 m
  f.log.steps[4].scan = scan_with_returns(kMinKeyframeReturns - 1);
  const auto sel = select_keyframes(f.log, f.poses, 0.5, 1.0);
  EXPECT_EQ(sel.too_few_returns, 1u);
  ASSERT_EQ(sel.keyframes.size(), 3u);
  EXPECT_EQ(sel.keyframes[1].scan, 5);  // the next scan far enough
  EXPECT_EQ(sel.keyframes[2].scan, 9);  // 0.5 m from that one
  const auto kfs = area_keyframes(f.log, sel.keyframes);
  ASSERT_EQ(kfs.size(), 3u);
  EXPECT_DOUBLE_EQ(kfs[1].pose.mean.x, 0.625);
  EXPECT_EQ(kfs[1].scan.size(), 181u);
}

}  // namespace
}  // namespace hmt::grouping

#include "hmt/framework/rtl.h"

#include <gtest/gtest.h>

namespace hmt::framework {
namespace {

TEST(RealTimeLocalizer, ComposesTheLatestEstimateWithTheOdometryNotYetProcessed) {
  MetricLayer layer;
  RealTimeLocalizer rtl(layer, 8);
  rtl.start();
  EXPECT_FALSE(rtl.request().get().valid);  // nothing processed yet

  MetricEstimate e;
  e.valid = true;
  e.step = 3;
  e.area = 2;
  e.pose_in_area = Pose2D(1.0, 2.0, 0.5);
  e.pose_continuous = Pose2D(10.0, 0.0, 0.5);
  layer.begin_step(3);
  layer.end_step(e);
  // Odometry of steps 3 (already in the estimate), 4 and 5.
  rtl.odometry(3, Pose2D(9.0, 9.0, 0.0));
  rtl.odometry(4, Pose2D(1.0, 0.0, 0.1));
  rtl.odometry(5, Pose2D(0.5, 0.0, 0.0));
  const RtlPose p = rtl.request().get();
  ASSERT_TRUE(p.valid);
  EXPECT_EQ(p.estimate_step, 3u);
  EXPECT_EQ(p.pending_odometry, 2u);
  EXPECT_EQ(p.area, 2u);
  const Pose2D want = e.pose_in_area + Pose2D(1.0, 0.0, 0.1) + Pose2D(0.5, 0.0, 0.0);
  EXPECT_NEAR(p.pose_in_area.x, want.x, 1e-12);
  EXPECT_NEAR(p.pose_in_area.y, want.y, 1e-12);
  EXPECT_NEAR(p.pose_in_area.theta, want.theta, 1e-12);
  const Pose2D want_c = e.pose_continuous + Pose2D(1.0, 0.0, 0.1) + Pose2D(0.5, 0.0, 0.0);
  EXPECT_NEAR(p.pose_continuous.x, want_c.x, 1e-12);

  // Metric SLAM catches up: the odometry it used is dropped.
  e.step = 5;
  layer.begin_step(5);
  layer.end_step(e);
  const RtlPose q = rtl.request().get();
  EXPECT_EQ(q.pending_odometry, 0u);
  EXPECT_NEAR(q.pose_in_area.x, 1.0, 1e-12);
  rtl.stop();
  EXPECT_THROW(rtl.request().get(), std::runtime_error);
}

}  // namespace
}  // namespace hmt::framework

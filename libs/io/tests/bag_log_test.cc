// The ROS-free part of the bag reader: transform chains and their
// interpolation, and the steps decided on a bag's first pass, on contents
// built in memory.
#include <gtest/gtest.h>

#include <cmath>

#include "bag_frames.h"
#include "bag_log.h"
#include "hmt/common/error.h"

namespace hmt::io::detail {
namespace {

BagTransform tf(double t, const std::string& parent, const std::string& child, double x,
                double y, double yaw) {
  BagTransform out;
  out.stamp = t;
  out.parent = parent;
  out.child = child;
  out.translation = Eigen::Vector3d(x, y, 0.0);
  out.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
  return out;
}

Pose2D at(const FrameTree& tree, const std::string& parent, const std::string& child,
          double t) {
  std::string why;
  const auto p = tree.lookup(parent, child, t, why);
  EXPECT_TRUE(p.has_value()) << why;
  return p ? planar(*p) : Pose2D();
}

TEST(BagFrames, InterpolatesBetweenSamples) {
  const FrameTree tree({tf(1.0, "odom", "base_link", 0.0, 0.0, 0.0),
                        tf(3.0, "odom", "base_link", 2.0, 4.0, 1.0)},
                       {}, "b");
  const Pose2D mid = at(tree, "odom", "base_link", 2.0);
  EXPECT_NEAR(mid.x, 1.0, 1e-12);
  EXPECT_NEAR(mid.y, 2.0, 1e-12);
  EXPECT_NEAR(mid.theta, 0.5, 1e-12);
  // At a sample, the sample itself.
  EXPECT_EQ(at(tree, "odom", "base_link", 3.0).x, 2.0);
  std::string why;
  EXPECT_FALSE(tree.lookup("odom", "base_link", 3.5, why));
  EXPECT_NE(why.find("no sample around 3.500000"), std::string::npos) << why;
  EXPECT_FALSE(tree.lookup("odom", "base_link", 0.5, why));
}

TEST(BagFrames, InterpolatesTheShortWayRound) {
  const FrameTree tree({tf(0.0, "odom", "base_link", 0.0, 0.0, 3.0),
                        tf(1.0, "odom", "base_link", 0.0, 0.0, -3.0)},
                       {}, "b");
  // From 3 to -3 rad through pi, not through 0.
  EXPECT_NEAR(std::abs(at(tree, "odom", "base_link", 0.5).theta), M_PI, 1e-9);
}

TEST(BagFrames, ComposesChainsUpAndDown) {
  // odom -> base_footprint (moving) -> base_link (static, 0.1 m up ignored
  // in the plane) -> laser (static, 0.3 m ahead, turned 90 degrees).
  const FrameTree tree({tf(0.0, "odom", "base_footprint", 1.0, 0.0, M_PI / 2),
                        tf(1.0, "odom", "base_footprint", 1.0, 0.0, M_PI / 2)},
                       {tf(0.0, "/base_footprint", "base_link", 0.0, 0.0, 0.0),
                        tf(0.0, "base_link", "laser", 0.3, 0.0, M_PI / 2)},
                       "b");
  const Pose2D odom_laser = at(tree, "odom", "laser", 0.5);
  EXPECT_NEAR(odom_laser.x, 1.0, 1e-12);
  EXPECT_NEAR(odom_laser.y, 0.3, 1e-12);
  EXPECT_NEAR(odom_laser.theta, M_PI, 1e-12);
  // Between siblings' descendants: the laser seen from the footprint.
  const Pose2D mount = at(tree, "base_footprint", "laser", 0.5);
  EXPECT_NEAR(mount.x, 0.3, 1e-12);
  EXPECT_NEAR(mount.theta, M_PI / 2, 1e-12);
  // And the other way round.
  const Pose2D back = at(tree, "laser", "odom", 0.5);
  const Pose2D id = odom_laser + back;
  EXPECT_NEAR(id.x, 0.0, 1e-12);
  EXPECT_NEAR(id.y, 0.0, 1e-12);
  EXPECT_NEAR(id.theta, 0.0, 1e-12);
  EXPECT_TRUE(tree.connected("odom", "laser"));
  EXPECT_FALSE(tree.connected("odom", "map"));
  std::string why;
  EXPECT_FALSE(tree.lookup("map", "laser", 0.5, why));
  EXPECT_NE(why.find("no chain of transforms connects 'map' and 'laser'"), std::string::npos);
}

TEST(BagFrames, RejectsWhatIsNotATree) {
  EXPECT_THROW(FrameTree({tf(0, "odom", "base_link", 0, 0, 0), tf(1, "map", "base_link", 0, 0, 0)},
                         {}, "b"),
               InputError);
  EXPECT_THROW(FrameTree({tf(0, "odom", "base_link", 0, 0, 0)},
                         {tf(0, "odom", "base_link", 0, 0, 0)}, "b"),
               InputError);
  BagTransform zero = tf(0, "odom", "base_link", 0, 0, 0);
  zero.rotation = Eigen::Quaterniond(0, 0, 0, 0);
  EXPECT_THROW(FrameTree({zero}, {}, "b"), InputError);
  // A cycle makes no common ancestor appear twice: lookups end.
  const FrameTree cycle({tf(0, "a", "b", 0, 0, 0), tf(0, "b", "a", 0, 0, 0)}, {}, "b");
  std::string why;
  cycle.lookup("a", "c", 0.0, why);
}

BagScanInfo scan_info(double stamp, const std::string& frame = "laser", size_t beams = 2) {
  BagScanInfo s;
  s.stamp = stamp;
  s.frame_id = frame;
  s.angle_increment = 0.1f;
  s.range_max = 5.0f;
  s.beams = beams;
  return s;
}

BagScan scan(const BagScanInfo& info) {
  return {info, std::vector<float>(info.beams, 1.0f)};
}

TEST(BagLog, OdometryTopicChildFrameIsTheRobotFrame) {
  // Odometry of base_footprint; the laser is mounted on base_link, 0.1 m
  // ahead of the footprint.
  BagContents c;
  c.topics = {{"/odom", kOdometryType, "", true, "", 2}, {"/scan", kLaserScanType, "", true, "", 1}};
  c.odometry["/odom"] = {tf(0.0, "odom", "base_footprint", 0, 0, 0),
                         tf(1.0, "odom", "base_footprint", 1, 0, 0)};
  c.tf_static = {tf(0, "base_footprint", "base_link", 0.1, 0, 0),
                 tf(0, "base_link", "laser", 0.2, 0, 0)};
  c.scans["/scan"] = {scan_info(0.5)};
  const BagSteps steps("b", c, BagOptions{});
  ASSERT_EQ(steps.steps(), 1u);
  LogStep step;
  ASSERT_TRUE(steps.step(0, scan(c.scans["/scan"][0]), step));
  EXPECT_NEAR(step.scan.sensor_pose.x, 0.3, 1e-12);
}

// Every decision is made on the first pass's contents, which hold no
// readings: which scans are steps, and whether their beams can be used.
TEST(BagLog, StepsAreDecidedBeforeTheReadings) {
  BagContents c;
  c.topics = {{"/odom", kOdometryType, "", true, "", 2}, {"/scan", kLaserScanType, "", true, "", 4}};
  c.odometry["/odom"] = {tf(1.0, "odom", "base_link", 0, 0, 0),
                         tf(3.0, "odom", "base_link", 2, 0, 0)};
  c.tf_static = {tf(0, "base_link", "laser", 0.2, 0, 0)};
  // One before the odometry (left out, so its lack of beams is no error),
  // two steps, one after the odometry (left out).
  c.scans["/scan"] = {scan_info(0.5, "laser", 0), scan_info(1.5), scan_info(2.5),
                      scan_info(3.5)};
  const BagSteps steps("b.bag", c, BagOptions{});
  EXPECT_EQ(steps.scan_topic(), "/scan");
  EXPECT_EQ(steps.messages(), 4u);
  EXPECT_EQ(steps.steps(), 2u);
  const std::vector<BagScanInfo>& infos = c.scans["/scan"];
  LogStep step;
  EXPECT_FALSE(steps.step(0, scan(infos[0]), step));
  ASSERT_TRUE(steps.step(1, scan(infos[1]), step));
  EXPECT_FALSE(step.has_odometry);
  EXPECT_EQ(step.scan.ranges.size(), 2u);
  ASSERT_TRUE(steps.step(2, scan(infos[2]), step));
  EXPECT_TRUE(step.has_odometry);
  EXPECT_NEAR(step.odometry_increment.x, 1.0, 1e-12);
  EXPECT_FALSE(steps.step(3, scan(infos[3]), step));

  // A message other than the one first read: the bag changed.
  for (const BagScan& other : {scan(scan_info(1.25)), scan(scan_info(1.5, "laser", 3)),
                               BagScan{infos[1], {1.0f}}}) {
    try {
      steps.step(1, other, step);
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind("ROS bag 'b.bag' changed while it was read (scan 1 on '/scan'", 0), 0u)
          << what;
    }
  }
  EXPECT_THROW(steps.step(4, scan(infos[3]), step), InputError);

  // A step's unusable beams are found before its readings are read, the
  // first one in the bag's order.
  c.scans["/scan"][2].range_max = -1.0f;
  c.scans["/scan"][1].beams = 0;
  try {
    BagSteps("b.bag", c, BagOptions{});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "ROS bag 'b.bag': scan 1 on '/scan' has no beams");
  }
}

}  // namespace
}  // namespace hmt::io::detail

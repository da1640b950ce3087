#include "hmt/experiments/building_sim.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hmt::experiments {
namespace {

TEST(experiments_BuildingSim, RaycastInABox) {
  World w;
  w.box(-5, -5, 5, 5);
  const RangeSensor s{"360", 2.0 * M_PI, 360, 20.0};
  const LaserScan scan = raycast(w, Pose2D(0, 0, 0.3), s);
  ASSERT_EQ(scan.size(), 360u);
  for (size_t i = 0; i < scan.size(); ++i) {
    ASSERT_TRUE(scan.valid[i]);
    const double a = 0.3 + scan.bearing(i);
    const double expect = 5.0 / std::max(std::fabs(std::cos(a)), std::fabs(std::sin(a)));
    EXPECT_NEAR(scan.ranges[i], expect, 1e-4) << i;
  }
  // Out of range: nothing valid.
  const LaserScan shortscan = raycast(w, Pose2D(), {"short", M_PI, 11, 4.0});
  for (uint8_t v : shortscan.valid) EXPECT_EQ(v, 0);
}

TEST(experiments_BuildingSim, NarrowSensorGeometry) {
  const auto sensors = standard_sensors(15.0);
  ASSERT_EQ(sensors.size(), 3u);
  EXPECT_NEAR(sensors[2].fov, 65.0 * M_PI / 180.0, 1e-12);
  World w;
  w.box(-5, -5, 5, 5);
  const LaserScan scan = raycast(w, Pose2D(), sensors[2]);
  EXPECT_NEAR(scan.bearing(0), -32.5 * M_PI / 180.0, 1e-6);
  EXPECT_NEAR(scan.bearing(scan.size() - 1), 32.5 * M_PI / 180.0, 1e-6);
  EXPECT_NEAR(scan.ranges[scan.size() / 2], 5.0, 1e-5);  // straight ahead
  for (const RangeSensor& s : sensors) EXPECT_EQ(s.max_range, 15.0);
}

TEST(experiments_BuildingSim, RoutePosesStepAndTurnInPlace) {
  // 2 m east, then 1 m north: 0.5 m steps, and a 90-degree turn with
  // keyframes at 30 and 60 degrees.
  const auto p = route_poses({{0, 0}, {2, 0}, {2, 1}}, 0.5, M_PI / 6);
  ASSERT_EQ(p.size(), 4u + 2u + 1u);
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(p[i].x, 0.5 * i, 1e-12);
    EXPECT_NEAR(p[i].theta, 0.0, 1e-12);
  }
  EXPECT_NEAR(p[4].x, 2.0, 1e-12);
  EXPECT_NEAR(p[4].theta, M_PI / 6, 1e-12);
  EXPECT_NEAR(p[5].theta, M_PI / 3, 1e-12);
  EXPECT_NEAR(p[6].y, 0.5, 1e-12);  // first step after the turn
  EXPECT_NEAR(p[6].theta, M_PI / 2, 1e-12);
  EXPECT_THROW(route_poses({{0, 0}, {1, 0}}, 0.0, 1.0), std::invalid_argument);
}

// Every route segment runs through free space, with clearance.
void expect_route_is_free(const World& w, const std::vector<Point2D>& route) {
  const RangeSensor ahead{"ahead", 0.02, 3, 100.0};
  for (size_t k = 0; k + 1 < route.size(); ++k) {
    const Point2D a = route[k], b = route[k + 1];
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    if (len == 0.0) continue;
    const Pose2D p(a.x, a.y, std::atan2(b.y - a.y, b.x - a.x));
    const LaserScan scan = raycast(w, p, ahead);
    if (scan.valid[1]) {
      EXPECT_GT(scan.ranges[1], len + 0.3) << "segment " << k;
    }
  }
  const RangeSensor around{"around", 2.0 * M_PI, 72, 100.0};
  for (const Pose2D& p : route_poses(route, 0.5, M_PI / 6)) {
    const LaserScan scan = raycast(w, p, around);
    for (size_t i = 0; i < scan.size(); ++i) {
      ASSERT_TRUE(scan.valid[i]) << "a closed world";
      EXPECT_GT(scan.ranges[i], 0.4) << p.x << " " << p.y;
    }
  }
}

TEST(experiments_BuildingSim, BuildingRouteStaysInFreeSpace) {
  expect_route_is_free(building(), building_route());
  const auto poses = route_poses(building_route(), 0.5, M_PI / 6);
  EXPECT_GT(poses.size(), 500u);
}

TEST(experiments_BuildingSim, TwoRoomsRouteStaysInFreeSpace) {
  expect_route_is_free(two_rooms(), two_rooms_route());
}

}  // namespace
}  // namespace hmt::experiments

#include "hmt/sim/ray_world.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace hmt::sim {
namespace {

TEST(sim_RayWorld, BeamStraightAtAWallReadsItsDistance) {
  World w;
  w.wall(2, -1, 2, 1);  // 2 m ahead
  Sensor s;
  s.beams = 3;
  s.fov = M_PI;  // beams at -90, 0 and +90 degrees
  s.max_range = 10.0;
  const LaserScan scan = raycast(w, Pose2D(0, 0, 0), s);
  ASSERT_EQ(scan.size(), 3u);
  EXPECT_NEAR(scan.bearing(0), -0.5 * M_PI, 1e-6);  // beam 0 on the right
  EXPECT_EQ(scan.valid[1], 1);
  EXPECT_NEAR(scan.ranges[1], 2.0, 1e-6);
  // The side beams see nothing: invalid, at max range.
  EXPECT_EQ(scan.valid[0], 0);
  EXPECT_EQ(scan.valid[2], 0);
  EXPECT_EQ(scan.ranges[0], 10.0f);
}

TEST(sim_RayWorld, WallBeyondMaxRangeIsInvalid) {
  World w;
  w.box(-5, -5, 5, 5);
  Sensor s;
  s.beams = 36;
  s.max_range = 4.0;
  const LaserScan scan = raycast(w, Pose2D(), s);
  for (uint8_t v : scan.valid) EXPECT_EQ(v, 0);
}

TEST(sim_RayWorld, FullCircleHasNoBeamTwice) {
  Sensor s;
  s.beams = 4;
  const LaserScan scan = raycast(World{}, Pose2D(), s);
  EXPECT_NEAR(scan.angle_increment, 0.5 * M_PI, 1e-6);
  EXPECT_NEAR(scan.bearing(0), -M_PI, 1e-6);
}

TEST(sim_RayWorld, NoiseWithASeedIsDeterministic) {
  World w;
  w.box(-5, -5, 5, 5);
  Sensor s;
  Random r1(7), r2(7);
  const LaserScan a = raycast(w, Pose2D(0.5, -1, 0.2), s, &r1, 0.05);
  const LaserScan b = raycast(w, Pose2D(0.5, -1, 0.2), s, &r2, 0.05);
  const LaserScan exact = raycast(w, Pose2D(0.5, -1, 0.2), s);
  ASSERT_EQ(a.size(), b.size());
  bool any_noise = false;
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.ranges[i], b.ranges[i]) << i;
    EXPECT_NEAR(a.ranges[i], exact.ranges[i], 0.5) << i;
    any_noise = any_noise || a.ranges[i] != exact.ranges[i];
  }
  EXPECT_TRUE(any_noise);
}

TEST(sim_RayWorld, BadSensorThrows) {
  Sensor s;
  s.beams = 1;
  EXPECT_THROW(raycast(World{}, Pose2D(), s), std::invalid_argument);
}

}  // namespace
}  // namespace hmt::sim

#include "hmt/area/area_size.h"

#include <gtest/gtest.h>

#include <cmath>

#include "hmt/common/config.h"
#include "hmt/common/error.h"

namespace hmt::area {
namespace {

TEST(AreaSize, PlaceNcutMatchesTheClosedFormsAt180And360Degrees) {
  // 360 degrees: every pair shares the whole view, a = c, Ncut = 1.
  EXPECT_NEAR(place_ncut(2.0 * M_PI), 1.0, 1e-9);
  // 180 degrees: overlap 1 - d / pi; within a half E = 2/3, across E = 1/3,
  // Ncut = 2 (1/3) / (2/3 + 1/3) = 2/3.
  EXPECT_NEAR(place_ncut(M_PI), 2.0 / 3.0, 1e-4);
  EXPECT_NEAR(tau_for_field_of_view(M_PI), 0.5, 1e-4);
  EXPECT_NEAR(tau_for_field_of_view(2.0 * M_PI), 0.75, 1e-9);
  // Wider than a full turn is a full turn.
  EXPECT_NEAR(place_ncut(10.0), 1.0, 1e-9);
}

TEST(AreaSize, PlaceNcutGrowsWithTheFieldOfView) {
  double last = 0.0;
  for (double deg = 30; deg <= 360; deg += 30) {
    const double n = place_ncut(deg * M_PI / 180.0);
    EXPECT_GT(n, last) << deg << " degrees";
    EXPECT_LE(n, 1.0 + 1e-12);
    last = n;
  }
}

LaserScan scan(size_t beams, double increment) {
  LaserScan s;
  s.angle_increment = static_cast<float>(increment);
  s.angle_min = static_cast<float>(-0.5 * increment * beams);
  s.ranges.assign(beams, 2.0f);
  s.valid.assign(beams, 1);
  return s;
}

TEST(AreaSize, ResolvesTauFromTheFirstScanWithBeams) {
  Log log;
  log.steps.resize(3);
  log.steps[1].scan = scan(1, 0.1);  // one beam: no field of view to read
  log.steps[2].scan = scan(361, M_PI / 360.0);
  AreaOptions o;
  o.partition.tau_from_sensor = true;
  o.partition.tau = 2.0;
  ASSERT_TRUE(resolve_tau(o, log));
  // The scan stores its increment as a float.
  EXPECT_NEAR(o.partition.tau, tau_for_field_of_view(361 * M_PI / 360.0), 1e-6);
  EXPECT_NEAR(o.partition.tau, 0.5, 0.01);

  AreaOptions fixed;
  fixed.partition.tau_from_sensor = false;
  fixed.partition.tau = 0.8;
  EXPECT_FALSE(resolve_tau(fixed, log));
  EXPECT_EQ(fixed.partition.tau, 0.8);

  AreaOptions none;
  EXPECT_FALSE(resolve_tau(none, Log{}));
}

TEST(AreaSize, ConfigReadsAutoOrANumber) {
  {
    Config cfg = Config::from_string("[area]\ntau = auto\n", "test");
    AreaOptions o;
    o.partition.tau_from_sensor = false;
    o.load(cfg);
    EXPECT_TRUE(o.partition.tau_from_sensor);
  }
  {
    Config cfg = Config::from_string("[area]\ntau = 0.7\n", "test");
    AreaOptions o;
    o.load(cfg);
    EXPECT_FALSE(o.partition.tau_from_sensor);
    EXPECT_EQ(o.partition.tau, 0.7);
  }
  {
    Config cfg = Config::from_string("[area]\ntau = often\n", "test");
    AreaOptions o;
    EXPECT_THROW(o.load(cfg), ConfigError);
  }
}

}  // namespace
}  // namespace hmt::area

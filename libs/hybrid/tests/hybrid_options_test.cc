#include "hmt/hybrid/hybrid_options.h"

#include <gtest/gtest.h>

#include <string>

#include "hmt/common/error.h"

namespace hmt::hybrid {
namespace {

HybridOptions load(const std::string& lines) {
  Config cfg = Config::from_string("[hmt]\n" + lines, "test");
  HybridOptions opt;
  opt.load(cfg);
  return opt;
}

TEST(HybridOptions, ArcFloorsGrowWithTheDistanceTheHeadingsOnlyUpToTheCap) {
  const HybridOptions opt = load(
      "arc_std_xy = 0.05\narc_std_xy_per_metre = 0.01\n"
      "arc_std_theta = 0.02\narc_std_theta_per_metre = 0.002\narc_std_theta_max = 0.1\n");
  EXPECT_DOUBLE_EQ(opt.arc_floor_xy(0.0), 0.05);
  EXPECT_DOUBLE_EQ(opt.arc_floor_xy(100.0), 1.05);  // the position's floor is not capped
  EXPECT_DOUBLE_EQ(opt.arc_floor_theta(0.0), 0.02);
  EXPECT_DOUBLE_EQ(opt.arc_floor_theta(10.0), 0.04);  // below the cap: as it grows
  EXPECT_DOUBLE_EQ(opt.arc_floor_theta(40.0), 0.1);   // the cap reached
  EXPECT_DOUBLE_EQ(opt.arc_floor_theta(100.0), 0.1);  // 0.22 uncapped
  EXPECT_DOUBLE_EQ(opt.arc_floor_theta(2000.0), 0.1);
}

TEST(HybridOptions, ArcHeadingCapZeroMeansNoCapAndNeverGoesBelowTheConstant) {
  const HybridOptions uncapped = load("arc_std_theta_max = 0\n");
  EXPECT_DOUBLE_EQ(uncapped.arc_floor_theta(100.0),
                   uncapped.arc_std_theta + uncapped.arc_std_theta_per_metre * 100.0);
  // A cap below the constant part leaves the constant.
  const HybridOptions low = load("arc_std_theta = 0.05\narc_std_theta_max = 0.01\n");
  EXPECT_DOUBLE_EQ(low.arc_floor_theta(0.0), 0.05);
  EXPECT_DOUBLE_EQ(low.arc_floor_theta(100.0), 0.05);
}

TEST(HybridOptions, TheDefaultsCapTheHeadingFloor) {
  const HybridOptions def = load("");
  EXPECT_GT(def.arc_std_theta_max, 0.0);
  EXPECT_LT(def.arc_floor_theta(1000.0), def.arc_std_theta + def.arc_std_theta_per_metre * 1000.0);
}

TEST(HybridOptions, RejectsBadArcFloors) {
  for (const char* line : {"arc_std_theta_max = -0.1\n", "arc_std_theta_max = nan\n",
                           "arc_std_theta_max = wide\n", "arc_std_theta = 0\n",
                           "arc_std_theta_per_metre = -1\n"}) {
    SCOPED_TRACE(line);
    EXPECT_THROW(load(line), ConfigError);
  }
}

}  // namespace
}  // namespace hmt::hybrid

#include "hmt/islands/localization_check.h"

#include <gtest/gtest.h>

#include <cmath>

#include "hmt/common/error.h"
#include "test_maps.h"

namespace hmt::islands {
namespace {

TEST(Spearman, RanksWithTies) {
  EXPECT_NEAR(spearman({1, 2, 3, 4}, {10, 20, 30, 40}), 1.0, 1e-12);
  EXPECT_NEAR(spearman({1, 2, 3, 4}, {4, 3, 2, 1}), -1.0, 1e-12);
  // Monotone but not linear: still 1.
  EXPECT_NEAR(spearman({1, 2, 3, 4}, {1, 8, 27, 1000}), 1.0, 1e-12);
  // Ranks of {1, 2, 2, 3} are {1, 2.5, 2.5, 4}; of {1, 3, 2, 4} {1, 3, 2, 4}:
  // Pearson of those by hand is 4.5 / sqrt(4.5 * 5).
  EXPECT_NEAR(spearman({1, 2, 2, 3}, {1, 3, 2, 4}), 4.5 / std::sqrt(4.5 * 5.0), 1e-12);
  EXPECT_EQ(spearman({1}, {2}), 0.0);
  EXPECT_EQ(spearman({1, 1, 1}, {1, 2, 3}), 0.0);
}

TEST(LocalizationCheck, CorridorErrorsExceedCornerErrorsAndRPredictsThem) {
  // The L of corridors of distinctiveness_test.cc: low R along its arms,
  // high at the bend and the dead ends are open.
  const OccupancyRaster m = test::walls(
      40, 40, 0.1, {{5, 12, 22, 12}, {22, 12, 22, 30}, {5, 14, 20, 14}, {20, 14, 20, 30}}, 0.0,
      {{5, 11.9, 22.1, 14}, {20, 11.9, 22.1, 30}});
  IslandsOptions o;
  o.normal_radius = 0.5;
  o.threads = 2;
  const DistinctivenessMap d = distinctiveness(m, o);
  CheckOptions c;
  c.samples = 150;
  metric_slam::MatcherOptions matcher;
  matcher.sigma = 0.05;
  const CheckResult r = localization_check(m, d, c, matcher, grid::InsertionOptions{});
  ASSERT_EQ(r.samples.size(), 150u);
  double low = 0, high = 0;
  int nl = 0, nh = 0;
  for (const CheckSample& s : r.samples) {
    EXPECT_GE(s.error_xy, 0.0);
    if (s.r < 0.2) {
      low += s.error_xy;
      ++nl;
    } else if (s.r > 0.6) {
      high += s.error_xy;
      ++nh;
    }
  }
  ASSERT_GT(nl, 10);
  ASSERT_GT(nh, 3);
  EXPECT_GT(low / nl, 1.2 * (high / nh));
  EXPECT_LT(r.spearman, -0.2);
  // The same seed gives the same samples.
  const CheckResult again = localization_check(m, d, c, matcher, grid::InsertionOptions{});
  EXPECT_EQ(again.samples.back().error_xy, r.samples.back().error_xy);
}

TEST(CheckOptions, InvalidValuesAreConfigurationErrors) {
  for (const std::string bad : {"samples = 0", "offset_min = -1", "offset_max = 0.05",
                                "angle_offset = 200", "beams = 1", "field_of_view = 0",
                                "max_range = 0"}) {
    SCOPED_TRACE(bad);
    Config cfg = Config::from_string("[islands_check]\n" + bad + "\n", "test");
    CheckOptions o;
    EXPECT_THROW(o.load(cfg), ConfigError);
  }
}

}  // namespace
}  // namespace hmt::islands

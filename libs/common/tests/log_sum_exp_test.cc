#include "hmt/common/log_sum_exp.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace hmt {
namespace {

TEST(LogSumExp, NeitherOverflowsNorLosesTheSmallTerms) {
  EXPECT_NEAR(log_sum_exp({1000.0, 1000.0}), 1000.0 + std::log(2.0), 1e-12);
  EXPECT_NEAR(log_sum_exp({-1000.0, -1000.0 + std::log(3.0)}), -1000.0 + std::log(4.0), 1e-12);
  EXPECT_EQ(log_sum_exp({}), -INFINITY);
  EXPECT_EQ(log_sum_exp({-INFINITY, -INFINITY}), -INFINITY);
}

TEST(NormalisedExp, GivesTheProbabilitiesOfLogWeightsOfAnyScale) {
  // Weights 1 : 3 : 6, shifted far beyond what exp() alone could take.
  const double shift = 800.0;
  const std::vector<double> p =
      normalised_exp({shift, shift + std::log(3.0), shift + std::log(6.0)});
  ASSERT_EQ(p.size(), 3u);
  EXPECT_NEAR(p[0], 0.1, 1e-12);
  EXPECT_NEAR(p[1], 0.3, 1e-12);
  EXPECT_NEAR(p[2], 0.6, 1e-12);
  EXPECT_TRUE(normalised_exp({}).empty());
}

}  // namespace
}  // namespace hmt

#include "hmt/common/int_div.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

namespace hmt {
namespace {

TEST(IntDiv, RoundsDownAndUpForEverySign) {
  for (int a = -40; a <= 40; ++a)
    for (int b : {-7, -3, -1, 1, 2, 5, 16}) {
      const double q = static_cast<double>(a) / b;
      EXPECT_EQ(floor_div(a, b), static_cast<int>(std::floor(q))) << a << " / " << b;
      EXPECT_EQ(ceil_div(a, b), static_cast<int>(std::ceil(q))) << a << " / " << b;
    }
}

TEST(IntDiv, WorksOnWideIntegers) {
  const int64_t big = int64_t{1} << 40;
  EXPECT_EQ(floor_div<int64_t>(-big - 1, 64), -(big / 64) - 1);
  EXPECT_EQ(ceil_div<int64_t>(big + 1, 64), big / 64 + 1);
  EXPECT_EQ(floor_div<int64_t>(-big, 64), -(big / 64));
}

}  // namespace
}  // namespace hmt

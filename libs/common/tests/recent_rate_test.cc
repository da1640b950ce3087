#include "hmt/common/recent_rate.h"

#include <gtest/gtest.h>

namespace hmt {
namespace {

TEST(RecentRate, NoRateBeforeTwoSamplesSpanTime) {
  RecentRate r(30.0);
  EXPECT_EQ(r.rate(), 0.0);
  r.add(0.0, 0);
  EXPECT_EQ(r.rate(), 0.0);
  r.add(0.0, 5);  // no time has passed: no rate yet
  EXPECT_EQ(r.rate(), 0.0);
}

TEST(RecentRate, SpansEverythingUntilTheWindowIsFull) {
  RecentRate r(30.0);
  r.add(0.0, 0);
  r.add(4.0, 100);
  r.add(10.0, 100);  // a pause counts too
  EXPECT_DOUBLE_EQ(r.rate(), 10.0);
}

TEST(RecentRate, FollowsASlowdownTheAverageHides) {
  // 20 items a second for 100 s, then 5 a second for 60 s: the average since
  // the start is 14.4, the last 30 s ran at 5.
  RecentRate r(30.0);
  size_t done = 0;
  for (int i = 0; i <= 1600; ++i) {
    const double t = 0.1 * i;
    r.add(t, done);
    done += t < 100.0 ? 2 : 0;
    if (t >= 100.0 && i % 2 == 0) ++done;
  }
  EXPECT_NEAR(r.rate(), 5.0, 0.2);
}

TEST(RecentRate, KeepsFewSamplesOnALongCount) {
  RecentRate r(30.0);
  for (int i = 0; i <= 100000; ++i) r.add(0.01 * i, static_cast<size_t>(i));
  EXPECT_NEAR(r.rate(), 100.0, 1e-6);
  EXPECT_LE(r.kept(), 34u);
}

}  // namespace
}  // namespace hmt

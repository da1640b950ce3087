#include "hmt/common/pose2d.h"

#include <gtest/gtest.h>

#include "hmt/common/random.h"

namespace hmt {
namespace {

TEST(Pose2D, ComposeThenRelativeIsIdentity) {
  Random rng(7);
  for (int i = 0; i < 100; ++i) {
    const Pose2D a(rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-3, 3));
    const Pose2D b(rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-3, 3));
    const Pose2D c = a + b;
    const Pose2D back = c - a;
    EXPECT_NEAR(back.x, b.x, 1e-9);
    EXPECT_NEAR(back.y, b.y, 1e-9);
    EXPECT_NEAR(wrap_angle(back.theta - b.theta), 0.0, 1e-9);
  }
}

TEST(Pose2D, KnownComposition) {
  const Pose2D a(1, 0, M_PI / 2);
  const Pose2D c = a + Pose2D(1, 0, 0);
  EXPECT_NEAR(c.x, 1.0, 1e-12);
  EXPECT_NEAR(c.y, 1.0, 1e-12);
  EXPECT_NEAR(c.theta, M_PI / 2, 1e-12);
}

TEST(WrapAngle, IntoHalfOpenInterval) {
  EXPECT_NEAR(wrap_angle(3 * M_PI), M_PI, 1e-12);
  EXPECT_NEAR(wrap_angle(-M_PI), M_PI, 1e-12);
  EXPECT_NEAR(wrap_angle(0.5), 0.5, 1e-12);
}

TEST(Random, SameSeedSameSequence) {
  Random a(42), b(42), c(43);
  bool differs = false;
  for (int i = 0; i < 50; ++i) {
    const double x = a.normal();
    EXPECT_EQ(x, b.normal());
    differs |= (x != c.normal());
  }
  EXPECT_TRUE(differs);
}

}  // namespace
}  // namespace hmt

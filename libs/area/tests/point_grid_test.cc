#include "hmt/area/point_grid.h"

#include <gtest/gtest.h>

#include <vector>

#include "hmt/common/random.h"

namespace hmt::area {
namespace {

bool brute_force_within(const std::vector<Point2D>& pts, const Point2D& p, double r) {
  for (const Point2D& q : pts)
    if ((q.x - p.x) * (q.x - p.x) + (q.y - p.y) * (q.y - p.y) <= r * r) return true;
  return false;
}

// Clustered points (walls and blobs) on both sides of the origin, queried
// inside, at the edge of and far outside the occupied cells, with radii from
// a fraction of a cell to many cells: the ring order, the disc clipping and
// the bounds clamp must give the brute force's answer every time.
TEST(area_PointGrid, AnyWithinMatchesBruteForceForSmallAndLargeRadii) {
  Random rng(7);
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<Point2D> pts;
    const int clusters = 1 + trial % 5;
    for (int c = 0; c < clusters; ++c) {
      const double cx = rng.uniform(-20.0, 20.0), cy = rng.uniform(-20.0, 20.0);
      for (int i = 0; i < 30; ++i)
        pts.push_back({cx + rng.normal(0.0, 1.5), cy + rng.normal(0.0, 0.3)});
    }
    const PointGrid grid(pts, 0.4);
    int hits = 0, misses = 0;
    for (int q = 0; q < 400; ++q) {
      const Point2D p{rng.uniform(-30.0, 30.0), rng.uniform(-30.0, 30.0)};
      const double r = q % 4 == 0 ? rng.uniform(0.01, 0.4) : rng.uniform(0.4, 8.0);
      const bool expected = brute_force_within(pts, p, r);
      ASSERT_EQ(grid.any_within(p, r), expected)
          << "trial " << trial << " query (" << p.x << ", " << p.y << ") r " << r;
      (expected ? hits : misses) += 1;
    }
    EXPECT_GT(hits, 0);
    EXPECT_GT(misses, 0);
  }
}

// A query exactly on a point, and one just beyond the radius across a cell
// border: the disc clipping must not drop the cell that holds the answer.
TEST(area_PointGrid, BoundaryDistancesAreKept) {
  const std::vector<Point2D> pts{{0.39, 0.0}, {-5.0, -5.0}};
  const PointGrid grid(pts, 0.4);
  EXPECT_TRUE(grid.any_within({0.39, 0.0}, 0.0));
  EXPECT_TRUE(grid.any_within({1.19, 0.0}, 0.8));
  EXPECT_FALSE(grid.any_within({1.19, 0.0}, 0.79));
  EXPECT_TRUE(grid.any_within({-5.0, -3.0}, 2.0));
  EXPECT_FALSE(grid.any_within({-5.0, -3.0}, 1.99));
  EXPECT_FALSE(PointGrid({}, 0.4).any_within({0.0, 0.0}, 100.0));
}

}  // namespace
}  // namespace hmt::area

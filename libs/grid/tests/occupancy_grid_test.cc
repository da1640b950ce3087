#include "hmt/grid/occupancy_grid.h"

#include <gtest/gtest.h>

#include <cmath>

#include "hmt/grid/scan_insertion.h"

namespace hmt::grid {
namespace {

LaserScan fan(int n, float range) {
  LaserScan s;
  s.angle_min = static_cast<float>(-M_PI / 2);
  s.angle_increment = static_cast<float>(M_PI / (n - 1));
  s.max_range = 80.0f;
  s.ranges.assign(n, range);
  s.valid.assign(n, 1);
  return s;
}

TEST(OccupancyGrid, UnknownUntilWritten) {
  OccupancyGrid g(0.05);
  EXPECT_EQ(g.find({3, -7}), nullptr);
  EXPECT_EQ(g.logodds({3, -7}), 0);
  g.mutable_cell({3, -7}).logodds = 12;
  EXPECT_EQ(g.logodds({3, -7}), 12);
  EXPECT_EQ(g.tile_count(), 1u);
  // Far away in negative coordinates: the table grows, old cells survive.
  g.mutable_cell({-5000, 4000}).logodds = -3;
  EXPECT_EQ(g.logodds({3, -7}), 12);
  EXPECT_EQ(g.logodds({-5000, 4000}), -3);
  EXPECT_EQ(g.tile_count(), 2u);
}

TEST(OccupancyGrid, CopiesShareTilesUntilWritten) {
  OccupancyGrid a(0.05);
  for (int i = 0; i < 200; ++i) a.mutable_cell({i, i}).logodds = 5;
  OccupancyGrid b = a;  // shares every tile
  size_t shared = 0;
  a.for_each_tile([&](const Tile* ta) {
    b.for_each_tile([&](const Tile* tb) { shared += (ta == tb); });
  });
  EXPECT_EQ(shared, a.tile_count());
  b.mutable_cell({0, 0}).logodds = 99;  // clones one tile of b only
  EXPECT_EQ(a.logodds({0, 0}), 5);
  EXPECT_EQ(b.logodds({0, 0}), 99);
  shared = 0;
  a.for_each_tile([&](const Tile* ta) {
    b.for_each_tile([&](const Tile* tb) { shared += (ta == tb); });
  });
  EXPECT_EQ(shared, a.tile_count() - 1);
}

TEST(ScanInsertion, HitsOccupiedRaysFree) {
  OccupancyGrid g(0.05);
  InsertionOptions opt;
  insert_scan(g, Pose2D(0, 0, 0), fan(181, 2.0f), opt);
  // Straight ahead at 2 m: occupied; at 1 m: free.
  EXPECT_GT(g.logodds(g.cell_of(2.0 + 0.01, 0.0)), 0);
  EXPECT_LT(g.logodds(g.cell_of(1.0, 0.0)), 0);
  // Behind the robot: never seen.
  EXPECT_EQ(g.logodds(g.cell_of(-1.0, 0.0)), 0);
  // The hit mean sits near the true end point (sub-cell precision).
  const CellIndex c = g.cell_of(2.0 + 1e-6, 0.0);
  const Cell* cell = g.find(c);
  ASSERT_NE(cell, nullptr);
  const Point2D m = g.hit_mean(c, *cell);
  EXPECT_NEAR(m.x, 2.0, 0.01);
}

TEST(ScanInsertion, ClampsLogOdds) {
  OccupancyGrid g(0.05);
  InsertionOptions opt;
  for (int i = 0; i < 100; ++i) insert_scan(g, Pose2D(0, 0.025, 0), fan(19, 1.02f), opt);
  // The robot sits on a cell centre line so the straight beam stays in row 0.
  EXPECT_EQ(g.logodds(g.cell_of(1.0 + 0.01, 0.025)), opt.l_clamp());
  EXPECT_EQ(g.logodds(g.cell_of(0.5, 0.025)), -opt.l_clamp());
}

TEST(ScanInsertion, BeyondMaxRangeOnlyFreesUpToIt) {
  OccupancyGrid g(0.05);
  InsertionOptions opt;
  opt.max_range = 1.0;
  insert_scan(g, Pose2D(), fan(181, 3.0f), opt);
  EXPECT_LT(g.logodds(g.cell_of(0.9, 0.0)), 0);
  EXPECT_EQ(g.logodds(g.cell_of(2.0, 0.0)), 0);
  EXPECT_EQ(g.logodds(g.cell_of(3.01, 0.0)), 0);
}

}  // namespace
}  // namespace hmt::grid

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
  EXPECT_FALSE(g.known({3, -7}));
  EXPECT_EQ(g.logodds({3, -7}), 0);
  g.mutable_logodds({3, -7}) = 12;
  EXPECT_EQ(g.logodds({3, -7}), 12);
  EXPECT_EQ(g.tile_count(), 1u);
  // Far away in negative coordinates: the table grows, old cells survive.
  g.mutable_logodds({-5000, 4000}) = -3;
  EXPECT_EQ(g.logodds({3, -7}), 12);
  EXPECT_EQ(g.logodds({-5000, 4000}), -3);
  EXPECT_EQ(g.tile_count(), 2u);
}

TEST(OccupancyGrid, CopiesShareTilesUntilWritten) {
  OccupancyGrid a(0.05);
  for (int i = 0; i < 200; ++i) a.mutable_logodds({i, i}) = 5;
  OccupancyGrid b = a;  // shares every tile
  size_t shared = 0;
  a.for_each_tile([&](const Tile* ta) {
    b.for_each_tile([&](const Tile* tb) { shared += (ta == tb); });
  });
  EXPECT_EQ(shared, a.tile_count());
  b.mutable_logodds({0, 0}) = 99;  // clones one tile of b only
  EXPECT_EQ(a.logodds({0, 0}), 5);
  EXPECT_EQ(b.logodds({0, 0}), 99);
  shared = 0;
  a.for_each_tile([&](const Tile* ta) {
    b.for_each_tile([&](const Tile* tb) { shared += (ta == tb); });
  });
  EXPECT_EQ(shared, a.tile_count() - 1);
}

// A copy shares every tile until one of the two is written; a grid of the
// same cells built on its own shares none.
TEST(OccupancyGrid, SharesEveryTileOnlyWithAnUnwrittenCopy) {
  OccupancyGrid a(0.05), twin(0.05);
  for (int i = 0; i < 200; ++i) a.mutable_logodds({i, i}) = twin.mutable_logodds({i, i}) = 5;
  OccupancyGrid b = a;
  EXPECT_TRUE(a.shares_every_tile_with(b));
  EXPECT_TRUE(b.shares_every_tile_with(a));
  EXPECT_FALSE(a.shares_every_tile_with(twin));
  b.mutable_logodds({3, 3}) = 5;  // the same value, yet a tile of b's own now
  EXPECT_FALSE(a.shares_every_tile_with(b));
  OccupancyGrid c = a;
  c.mutable_logodds({5000, 5000}) = 1;  // a new tile: the table grows
  EXPECT_FALSE(a.shares_every_tile_with(c));
  EXPECT_FALSE(a.shares_every_tile_with(OccupancyGrid(0.1)));
  EXPECT_TRUE(OccupancyGrid(0.05).shares_every_tile_with(OccupancyGrid(0.05)));
}

TEST(OccupancyGrid, HitStatisticsOnlyInTilesThatWereHit) {
  // A fan of 10 m beams: the tiles around the arc of hits hold hit
  // statistics, the tiles the rays only cross do not (a quarter of the size).
  OccupancyGrid g(0.05);
  insert_scan(g, Pose2D(0, 0, 0), fan(361, 10.0f), InsertionOptions{});
  size_t with_hits = 0, without = 0;
  g.for_each_tile([&](const Tile* t) { (t->hit_means ? with_hits : without) += 1; });
  EXPECT_GT(with_hits, 0u);
  EXPECT_GT(without, with_hits);  // the half-disc's inside outweighs its rim
  EXPECT_EQ(g.tile_bytes(),
            g.tile_count() * sizeof(Tile) + with_hits * sizeof(Tile::HitPlane));
  // Cells of a tile without the plane read as never hit.
  const CellIndex inside = g.cell_of(2.0, 0.0);
  ASSERT_EQ(g.tile_of(inside)->hit_means, nullptr);
  EXPECT_EQ(g.cell(inside).hits, 0);
  EXPECT_LT(g.cell(inside).logodds, 0);
  // Copy-on-write copies the plane with the tile: the copies are independent.
  const CellIndex rim = g.cell_of(10.0 + 1e-6, 0.0);
  OccupancyGrid copy = g;
  Cell c = g.cell(rim);
  ASSERT_GT(c.hits, 0);
  c.hits = 200;
  copy.set_cell(rim, c);
  EXPECT_EQ(copy.cell(rim).hits, 200);
  EXPECT_NE(g.cell(rim).hits, 200);
  // Setting a cell without hit statistics does not create the plane.
  OccupancyGrid h(0.05);
  h.set_cell({1, 1}, Cell{-10, 0, 0, 0});
  EXPECT_EQ(h.tile_of({1, 1})->hit_means, nullptr);
  h.set_cell({2, 1}, Cell{30, 1, 5, -5});
  ASSERT_NE(h.tile_of({2, 1})->hit_means, nullptr);
  EXPECT_EQ(h.cell({2, 1}).hx, 5);
  EXPECT_EQ(h.cell({1, 1}).logodds, -10);
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
  ASSERT_TRUE(g.known(c));
  const Point2D m = g.hit_mean(c, g.cell(c));
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

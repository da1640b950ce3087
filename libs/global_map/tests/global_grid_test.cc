#include "hmt/global_map/global_grid.h"

#include <gtest/gtest.h>

#include <memory>
#include <set>
#include <stdexcept>
#include <utility>

namespace hmt::global_map {
namespace {

using topology::HmtMap;
using topology::PoseGaussian;
using CellSet = std::set<std::pair<int, int>>;

constexpr double kRes = 0.1;

// A local map whose only content is a wall along x: cells (0..9, row),
// occupied with the given log-odds and hit count.
std::shared_ptr<grid::OccupancyGrid> wall_map(int row, int logodds = 80,
                                              int hits = 3) {
  auto g = std::make_shared<grid::OccupancyGrid>(kRes);
  for (int x = 0; x < 10; ++x) {
    grid::Cell c;
    c.logodds = static_cast<grid::LogOdds>(logodds);
    c.hits = static_cast<uint8_t>(hits);
    g->set_cell({x, row}, c);
  }
  return g;
}

CellSet occupied_cells(const grid::OccupancyGrid& g) {
  CellSet cells;
  grid::CellIndex lo, hi;
  if (!g.bounds(&lo, &hi)) return cells;
  for (int y = lo.y; y <= hi.y; ++y)
    for (int x = lo.x; x <= hi.x; ++x)
      if (g.logodds({x, y}) > 0) cells.insert({x, y});
  return cells;
}

GlobalPoses poses_of(std::initializer_list<std::pair<AreaId, Pose2D>> list) {
  GlobalPoses g;
  g.root = list.begin()->first;
  for (const auto& [id, p] : list) g.poses.emplace(id, PoseGaussian(p));
  return g;
}

TEST(RenderGlobalGrid, WallsLandWhereThePosesPutThem) {
  HmtMap m;
  m.add_area(0);
  m.add_area(1);
  m.add_area(2);
  m.set_map(0, wall_map(5));  // y = 0.55, x in [0, 1)
  m.set_map(1, wall_map(2));  // y = 0.25 in area 1's frame
  m.set_map(2, wall_map(0));  // unreachable: not drawn
  // Area 1 turned by 90 degrees at (3, 1): its x axis points along global
  // y, so its wall runs up from (3 - 0.25, 1) to (2.75, 2).
  GlobalPoses poses = poses_of({{0, Pose2D(0, 0, 0)},
                                {1, Pose2D(3.0, 1.0, M_PI / 2)}});
  poses.unreachable = {2};

  const grid::OccupancyGrid g = render_global_grid(m, poses, kRes);
  CellSet expected;
  for (int i = 0; i < 10; ++i) {
    expected.insert({i, 5});    // area 0, as it was
    expected.insert({27, 10 + i});  // area 1, rotated
  }
  EXPECT_EQ(occupied_cells(g), expected);
  ASSERT_TRUE(g.known({27, 14}));
  const grid::Cell c = g.cell({27, 14});
  EXPECT_EQ(c.logodds, 80);
  EXPECT_EQ(c.hits, 3);
  EXPECT_EQ(c.hx, 0);
  EXPECT_EQ(c.hy, 0);
}

TEST(RenderGlobalGrid, HalfTurnAndCoarserResolution) {
  HmtMap m;
  m.add_area(0);
  m.add_area(4);
  m.set_map(4, wall_map(3));  // y = 0.35, x in [0, 1)
  // Turned by 180 degrees at (-1.05, 2.05): the wall's cells cover x in
  // (-2.05, -1.05], y in (1.65, 1.75]. On a 0.2 m grid the centres of row 8,
  // columns -10..-6 fall on it (on wall cell centres, so rounding cannot
  // move the lookup across a cell border).
  const GlobalPoses poses =
      poses_of({{0, Pose2D()}, {4, Pose2D(-1.05, 2.05, M_PI)}});
  const grid::OccupancyGrid g = render_global_grid(m, poses, 0.2);
  CellSet expected;
  for (int x = -10; x <= -6; ++x) expected.insert({x, 8});
  EXPECT_EQ(occupied_cells(g), expected);
}

TEST(RenderGlobalGrid, OverlapsAddAndSaturate) {
  HmtMap m;
  for (AreaId i = 0; i < 3; ++i) m.add_area(i);
  m.set_map(0, wall_map(0, 100, 2));
  m.set_map(1, wall_map(0, 100, 9));
  auto freed = wall_map(0, -30, 0);
  m.set_map(2, freed);
  const GlobalPoses both = poses_of({{0, Pose2D()}, {1, Pose2D()}});
  const grid::OccupancyGrid sum = render_global_grid(m, both, kRes);
  EXPECT_EQ(sum.logodds({4, 0}), 127);  // 200 saturates
  EXPECT_EQ(sum.cell({4, 0}).hits, 9);  // the larger count

  const GlobalPoses mixed = poses_of({{0, Pose2D()}, {2, Pose2D()}});
  EXPECT_EQ(render_global_grid(m, mixed, kRes).logodds({4, 0}), 70);
  // Saturation also holds at the free end.
  m.set_map(1, wall_map(0, -100, 0));
  m.set_map(0, wall_map(0, -100, 0));
  EXPECT_EQ(render_global_grid(m, both, kRes).logodds({4, 0}), -127);
}

TEST(RenderGlobalGrid, AreasWithoutMapsAndBadArguments) {
  HmtMap m;
  m.add_area(0);
  m.add_area(1);
  const GlobalPoses poses = poses_of({{0, Pose2D()}, {1, Pose2D(1, 1, 0)}});
  grid::CellIndex lo, hi;
  EXPECT_FALSE(render_global_grid(m, poses, kRes).bounds(&lo, &hi));
  EXPECT_THROW(render_global_grid(m, poses, 0.0), std::invalid_argument);
  EXPECT_THROW(render_global_grid(m, poses, NAN), std::invalid_argument);
  const GlobalPoses foreign = poses_of({{0, Pose2D()}, {5, Pose2D()}});
  EXPECT_THROW(render_global_grid(m, foreign, kRes), std::invalid_argument);
}

}  // namespace
}  // namespace hmt::global_map

// Synthetic grids for the alignment tests: a walled room ray-cast by hmt_sim
// and inserted with hmt_grid's inverse sensor model, seen from any frame.
#pragma once

#include <functional>
#include <vector>

#include "hmt/common/pose2d.h"
#include "hmt/common/random.h"
#include "hmt/grid/occupancy_grid.h"
#include "hmt/grid/scan_insertion.h"
#include "hmt/sim/ray_world.h"

namespace hmt::alignment::testing {

// A 20 x 20 m room: an inner partition with a doorway, an L-shaped wall, a
// few pillars of different sizes; nothing symmetric.
inline sim::World room_world() {
  sim::World w;
  w.box(0, 0, 20, 20);
  w.wall(7, 0, 7, 8);          // partition with a doorway (8..10)
  w.wall(7, 10, 7, 13);
  w.wall(13, 14, 13, 20);      // L-shaped wall
  w.wall(13, 14, 17, 14);
  w.wall(0, 16, 3.5, 16);      // stub from the west wall
  w.box(3, 4, 3.6, 4.6);       // pillars
  w.box(11, 5, 11.4, 5.4);
  w.box(16, 6, 17.2, 7.0);
  w.box(9.5, 16.5, 10.3, 17.3);
  return w;
}

// Robot positions (world frame) the room is scanned from.
inline std::vector<Pose2D> room_tour_a() {
  return {{2, 2, 0.3},   {4, 12, -1.0}, {5, 18, 0.5}, {10, 9, 2.0},
          {15, 3, 1.0},  {18, 11, -2.5}, {16, 18, 0.2}, {10, 13, -0.7},
          {11, 2, 2.8}};
}
inline std::vector<Pose2D> room_tour_b() {
  return {{2.5, 3, -0.4}, {3.5, 13, 1.2}, {6, 17.5, -2.0}, {9.5, 8, 0.1},
          {14.5, 2.5, 2.2}, {18.5, 10, 0.9}, {15.5, 17, -1.5}, {11, 12.5, 3.0},
          {10, 3, -1.2}};
}

// The grid of `world` scanned from `tour` (world poses), built in the frame
// whose pose in the world is `frame`. Each range gets N(0, sigma) noise from
// a generator seeded with `seed`.
inline grid::OccupancyGrid scanned_grid(const sim::World& world,
                                        const std::vector<Pose2D>& tour,
                                        const Pose2D& frame, uint64_t seed,
                                        double sigma = 0.01,
                                        double resolution = 0.05) {
  grid::OccupancyGrid g(resolution);
  sim::Sensor sensor;
  sensor.beams = 720;
  sensor.max_range = 20.0;
  Random rng(seed);
  const grid::InsertionOptions ins;
  for (const Pose2D& w : tour) {
    const LaserScan scan = sim::raycast(world, w, sensor, &rng, sigma);
    // The same scan inserted a few times: a well-observed map.
    for (int k = 0; k < 3; ++k) grid::insert_scan(g, w - frame, scan, ins);
  }
  return g;
}

// The cells of `g` (built in `frame`) whose centres, in world coordinates,
// satisfy `keep`.
inline grid::OccupancyGrid crop(const grid::OccupancyGrid& g, const Pose2D& frame,
                                const std::function<bool(const Point2D&)>& keep) {
  grid::OccupancyGrid out(g.resolution());
  grid::CellIndex lo, hi;
  if (!g.bounds(&lo, &hi)) return out;
  for (int y = lo.y; y <= hi.y; ++y)
    for (int x = lo.x; x <= hi.x; ++x) {
      const grid::Cell c = g.cell({x, y});  // unknown space: all zero
      if (c.logodds == 0 && c.hits == 0) continue;
      if (keep(frame.transform(g.cell_center({x, y})))) out.set_cell({x, y}, c);
    }
  return out;
}

}  // namespace hmt::alignment::testing

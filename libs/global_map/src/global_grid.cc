#include "hmt/global_map/global_grid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace hmt::global_map {
namespace {

constexpr int kLogOddsLimit = 127;

struct CellBox {
  grid::CellIndex lo, hi;  // inclusive
};

// The cells of `target` that the area grid's allocated rectangle covers
// once it is placed at `pose`: the bounding box of its four corners.
CellBox covered_cells(const grid::OccupancyGrid& area, const Pose2D& pose,
                      const grid::OccupancyGrid& target) {
  grid::CellIndex lo, hi;
  area.bounds(&lo, &hi);
  const double r = area.resolution();
  const double xs[2] = {lo.x * r, (hi.x + 1) * r};
  const double ys[2] = {lo.y * r, (hi.y + 1) * r};
  double min_x = INFINITY, min_y = INFINITY, max_x = -INFINITY,
         max_y = -INFINITY;
  for (const double x : xs)
    for (const double y : ys) {
      const Point2D p = pose.transform({x, y});
      min_x = std::min(min_x, p.x);
      min_y = std::min(min_y, p.y);
      max_x = std::max(max_x, p.x);
      max_y = std::max(max_y, p.y);
    }
  return {target.cell_of(min_x, min_y), target.cell_of(max_x, max_y)};
}

void add_into(grid::Tile& to, int i, const grid::Cell& from) {
  const int sum = std::clamp<int>(to.logodds[i] + from.logodds, -kLogOddsLimit,
                                  kLogOddsLimit);
  to.logodds[i] = static_cast<grid::LogOdds>(sum);
  if (from.hits > to.hit(i).hits) to.mutable_hit(i).hits = from.hits;
}

void draw_area(const grid::OccupancyGrid& area, const Pose2D& pose,
               grid::OccupancyGrid& target) {
  grid::CellIndex unused_lo, unused_hi;
  if (!area.bounds(&unused_lo, &unused_hi)) return;  // nothing archived
  const Pose2D to_area = pose.inverse();
  const CellBox box = covered_cells(area, pose, target);
  for (int y = box.lo.y; y <= box.hi.y; ++y)
    for (int x = box.lo.x; x <= box.hi.x; ++x) {
      const Point2D local = to_area.transform(target.cell_center({x, y}));
      const grid::Cell source = area.cell(area.cell_of(local.x, local.y));
      if (source.logodds == 0 && source.hits == 0) continue;  // or unknown
      add_into(target.mutable_tile(x >> grid::kTileBits, y >> grid::kTileBits),
               grid::OccupancyGrid::index_in_tile({x, y}), source);
    }
}

}  // namespace

grid::OccupancyGrid render_global_grid(const topology::HmtMap& map,
                                       const GlobalPoses& poses,
                                       double resolution) {
  if (!(resolution > 0.0) || !std::isfinite(resolution))
    throw std::invalid_argument(
        "render_global_grid: resolution must be positive and finite");
  grid::OccupancyGrid out(resolution);
  // Ascending area ids (std::map order): the saturating sum depends on the
  // order once it saturates, and this keeps it deterministic.
  for (const auto& [id, pose] : poses.poses) {
    if (!map.has_area(id))
      throw std::invalid_argument("render_global_grid: the poses name area " +
                                  std::to_string(id) +
                                  ", which the map does not have");
    const auto& area_map = map.area(id).map;
    if (area_map) draw_area(*area_map, pose.mean, out);
  }
  return out;
}

}  // namespace hmt::global_map

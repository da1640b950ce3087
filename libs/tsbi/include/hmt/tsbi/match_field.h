// Where an area map's obstacles are, as a raster of the Chebyshev distance
// (in cells) from every cell to the nearest cell the scan matcher counts as
// an obstacle (log-odds at or above its threshold). Built once per archived
// area map and shared by every hypothesis and new-area event that weighs
// that area: the map never changes once archived.
//
// It answers two questions with one lookup per observation point:
//  - could the matcher match enough points anywhere in the prior's gate?
//    (may_reach_ratio below: an upper bound, to skip hopeless areas), and
//  - how well does a lattice pose fit? (the wide search's coarse score).
#pragma once

#include <cstdint>
#include <vector>

#include "hmt/common/pose2d.h"
#include "hmt/grid/occupancy_grid.h"
#include "hmt/topology/pose_gaussian.h"

namespace hmt::tsbi {

class MatchField {
 public:
  static constexpr int kFar = 255;  // distances are capped here

  // `occupied`: the scan matcher's obstacle threshold (log-odds).
  MatchField(const grid::OccupancyGrid& map, grid::LogOdds occupied);

  double resolution() const { return resolution_; }
  bool has_obstacles() const { return !d_.empty(); }

  // Chebyshev distance (cells, capped at kFar) from cell (cx, cy) to the
  // nearest obstacle. Outside the raster, which spans the obstacles'
  // bounding box, the distance to that box: a lower bound.
  int distance(int cx, int cy) const {
    const int ix = cx - x0_, iy = cy - y0_;
    if (static_cast<unsigned>(ix) < static_cast<unsigned>(w_) &&
        static_cast<unsigned>(iy) < static_cast<unsigned>(h_))
      return d_[static_cast<size_t>(iy) * w_ + ix];
    return outside_distance(ix, iy);
  }
  int distance_at(double x, double y) const {
    return distance(floor_cell(x * inv_resolution_), floor_cell(y * inv_resolution_));
  }
  size_t bytes() const { return d_.size(); }
  // The raster: first cell and size; it spans the obstacles' bounding box.
  int x0() const { return x0_; }
  int y0() const { return y0_; }
  int width() const { return w_; }
  int height() const { return h_; }

  static int floor_cell(double v) {
    const int i = static_cast<int>(v);
    return i - (v < i);
  }

 private:
  int outside_distance(int ix, int iy) const;

  double resolution_, inv_resolution_;
  int x0_ = 0, y0_ = 0, w_ = 0, h_ = 0;  // raster origin (cell index) and size
  std::vector<uint8_t> d_;              // row-major, w_ x h_
};

// Whether some pose in the gate of `prior` (squared Mahalanobis distance to
// its mean at most `gate`) could let the scan matcher, with search radius
// `window` cells, match at least `min_ratio` of `points` (robot frame).
//
// False only when no such pose exists: then no match of these points can
// pass TSBI's match-ratio gate, and the area cannot be a candidate. The
// proof is a branch and bound over boxes of poses: moving the pose within a
// box of half-widths (hx, hy, ht) moves a point at range r by at most
// hypot(hx, hy) + r ht, i.e. its cell by at most ceil(that / resolution)
// cells per axis, so the point can be matched somewhere in the box only if
// an obstacle lies within window + that many cells of its cell at the box's
// centre. Boxes whose count cannot reach the ratio, or that lie outside the
// gate, are dropped; the others are split. True as soon as a box small
// enough (about two cells of motion) still passes, or when `max_boxes` boxes
// were examined without a proof.
bool may_reach_ratio(const MatchField& field, const std::vector<Point2D>& points,
                     const topology::PoseGaussian& prior, double gate, double min_ratio,
                     int window, int max_boxes);

}  // namespace hmt::tsbi

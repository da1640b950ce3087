// A static uniform hash grid over 2D points, for "is there a point within r
// of p?" queries.
//
// Why not a k-d tree (nanoflann, as bundled with MRPT): the SSO only asks
// "is any point within r?". With the fixed tolerance r = delta and cells of
// 2*delta a query touches at most 2x2 cells, O(1) work whatever the scan
// size; the probabilistic test's r grows with the point's range (its gate
// covers the sampling term r beta), and any_near() then visits the cells
// nearest first, so a match ends the query early. Building is one sort:
// cheaper than a tree build and a tree descent per query, and free of extra
// dependencies.
//
// Points are stored sorted by cell so each cell is a contiguous run; the cell
// table is open-addressed (linear probing) on a 64-bit key.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "hmt/common/pose2d.h"

namespace hmt::checkpoint {
struct Access;  // hmt/checkpoint/checkpoint.h
}  // namespace hmt::checkpoint

namespace hmt::area {

class PointGrid {
  // Checkpoints save and restore every member, bit for bit.
  friend struct hmt::checkpoint::Access;

 public:
  PointGrid() = default;
  // `cell` > 0. The grid keeps a copy of the points (reordered by cell) and
  // each point's index in `points`.
  PointGrid(const std::vector<Point2D>& points, double cell);

  bool empty() const { return pts_.empty(); }
  double cell_size() const { return cell_; }

  // True if some stored point q has |q - p| <= r.
  bool any_within(const Point2D& p, double r) const {
    const double r2 = r * r;
    return any_near(p, r, [&](const Point2D& q, uint32_t) {
      const double dx = q.x - p.x, dy = q.y - p.y;
      return dx * dx + dy * dy <= r2;
    });
  }

  // Calls pred(point, original_index) for stored points in the cells that
  // meet the disc of radius r around p until one returns true; returns
  // whether one did. The cells are visited ring by ring outward from p's
  // cell: the SSO's gate radius reaches many cells for a far point (its
  // covariance grows with range), and the point that answers "yes" is
  // usually in or next to p's cell, so a hit ends the search after a few
  // lookups instead of after the square's far corners. Cells wholly farther
  // than r from p, and cells outside the occupied ones' bounds, are never
  // looked up. Whether some point answers does not depend on the order.
  template <class Pred>
  bool any_near(const Point2D& p, double r, Pred&& pred) const {
    if (pts_.empty()) return false;
    const int64_t x0 = std::max(cell_of(p.x - r), lo_x_), x1 = std::min(cell_of(p.x + r), hi_x_);
    const int64_t y0 = std::max(cell_of(p.y - r), lo_y_), y1 = std::min(cell_of(p.y + r), hi_y_);
    if (x0 > x1 || y0 > y1) return false;
    const int64_t cx = cell_of(p.x), cy = cell_of(p.y);
    const int64_t rings = std::max(std::max(cx - x0, x1 - cx), std::max(cy - y0, y1 - cy));
    const double r2 = r * r;
    const auto visit = [&](int64_t ix, int64_t iy) {
      // Distance from p to the cell's nearest point, per axis.
      const double dx = std::max({0.0, static_cast<double>(ix) * cell_ - p.x,
                                  p.x - static_cast<double>(ix + 1) * cell_});
      const double dy = std::max({0.0, static_cast<double>(iy) * cell_ - p.y,
                                  p.y - static_cast<double>(iy + 1) * cell_});
      if (dx * dx + dy * dy > r2) return false;
      const Cell* c = find(key(ix, iy));
      if (!c) return false;
      for (uint32_t k = c->begin; k < c->end; ++k)
        if (pred(pts_[k], idx_[k])) return true;
      return false;
    };
    for (int64_t ring = 0; ring <= rings; ++ring) {
      const int64_t ya = std::max(y0, cy - ring), yb = std::min(y1, cy + ring);
      for (int64_t ix = std::max(x0, cx - ring); ix <= std::min(x1, cx + ring); ++ix) {
        if (ix == cx - ring || ix == cx + ring) {  // a whole column of the ring
          for (int64_t iy = ya; iy <= yb; ++iy)
            if (visit(ix, iy)) return true;
        } else {  // only the ring's top and bottom cells
          if (cy - ring >= y0 && visit(ix, cy - ring)) return true;
          if (ring > 0 && cy + ring <= y1 && visit(ix, cy + ring)) return true;
        }
      }
    }
    return false;
  }

  static uint64_t key(int64_t ix, int64_t iy) {
    return (static_cast<uint64_t>(static_cast<uint32_t>(ix)) << 32) |
           static_cast<uint32_t>(iy);
  }
  // floor(v / cell) without a call into libm (std::floor is one on the
  // baseline x86-64 target, six per query): the same integer for every
  // finite coordinate.
  int64_t cell_of(double v) const {
    const double f = v * inv_cell_;
    const int64_t i = static_cast<int64_t>(f);
    return i - (f < static_cast<double>(i));
  }

 private:
  struct Cell {
    uint64_t key;
    uint32_t begin, end;
  };
  const Cell* find(uint64_t k) const {
    size_t h = hash(k) & mask_;
    while (true) {
      const uint32_t slot = table_[h];
      if (slot == 0) return nullptr;
      const Cell& c = cells_[slot - 1];
      if (c.key == k) return &c;
      h = (h + 1) & mask_;
    }
  }
  static size_t hash(uint64_t k) {
    // splitmix64 finaliser: spreads neighbouring cells over the table.
    k ^= k >> 30;
    k *= 0xbf58476d1ce4e5b9ULL;
    k ^= k >> 27;
    k *= 0x94d049bb133111ebULL;
    k ^= k >> 31;
    return static_cast<size_t>(k);
  }

  double cell_ = 1.0, inv_cell_ = 1.0;
  std::vector<Point2D> pts_;   // sorted by cell
  std::vector<uint32_t> idx_;  // original index of pts_[k]
  std::vector<Cell> cells_;
  std::vector<uint32_t> table_;  // 0 = empty, else index into cells_ + 1
  size_t mask_ = 0;
  // Bounds of the occupied cells (derived from cells_: set_bounds()).
  int64_t lo_x_ = 0, hi_x_ = -1, lo_y_ = 0, hi_y_ = -1;
  void set_bounds();
};

}  // namespace hmt::area

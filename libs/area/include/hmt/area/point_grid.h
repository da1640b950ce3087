// A static uniform hash grid over 2D points, for "is there a point within r
// of p?" queries.
//
// Why not a k-d tree (nanoflann, as bundled with MRPT): the SSO only asks a
// fixed-radius existence question with r equal to the match tolerance delta.
// With cells of size 2*delta a query touches at most 2x2 cells, i.e. O(1)
// work whatever the scan size, and building is one sort — cheaper than a tree
// build and a tree descent per query, and free of extra dependencies.
//
// Points are stored sorted by cell so each cell is a contiguous run; the cell
// table is open-addressed (linear probing) on a 64-bit key.
#pragma once

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

  // Calls pred(point, original_index) for stored points in the cells covering
  // the square [p - r, p + r] until one returns true; returns whether one did.
  template <class Pred>
  bool any_near(const Point2D& p, double r, Pred&& pred) const {
    if (pts_.empty()) return false;
    const int64_t x0 = cell_of(p.x - r), x1 = cell_of(p.x + r);
    const int64_t y0 = cell_of(p.y - r), y1 = cell_of(p.y + r);
    for (int64_t ix = x0; ix <= x1; ++ix) {
      for (int64_t iy = y0; iy <= y1; ++iy) {
        const Cell* c = find(key(ix, iy));
        if (!c) continue;
        for (uint32_t k = c->begin; k < c->end; ++k)
          if (pred(pts_[k], idx_[k])) return true;
      }
    }
    return false;
  }

  static uint64_t key(int64_t ix, int64_t iy) {
    return (static_cast<uint64_t>(static_cast<uint32_t>(ix)) << 32) |
           static_cast<uint32_t>(iy);
  }
  int64_t cell_of(double v) const {
    return static_cast<int64_t>(std::floor(v * inv_cell_));
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
};

}  // namespace hmt::area

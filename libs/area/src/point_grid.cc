#include "hmt/area/point_grid.h"

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace hmt::area {

PointGrid::PointGrid(const std::vector<Point2D>& points, double cell)
    : cell_(cell), inv_cell_(1.0 / cell) {
  if (!(cell > 0.0)) throw std::invalid_argument("PointGrid: cell must be > 0");
  const size_t n = points.size();
  std::vector<uint64_t> keys(n);
  for (size_t i = 0; i < n; ++i)
    keys[i] = key(cell_of(points[i].x), cell_of(points[i].y));
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return keys[a] != keys[b] ? keys[a] < keys[b] : a < b;
  });
  pts_.resize(n);
  idx_.resize(n);
  for (size_t k = 0; k < n; ++k) {
    pts_[k] = points[order[k]];
    idx_[k] = order[k];
    if (k == 0 || keys[order[k]] != keys[order[k - 1]])
      cells_.push_back({keys[order[k]], static_cast<uint32_t>(k), 0});
    cells_.back().end = static_cast<uint32_t>(k + 1);
  }
  size_t cap = 16;
  while (cap < 2 * cells_.size()) cap <<= 1;
  table_.assign(cap, 0);
  mask_ = cap - 1;
  for (size_t c = 0; c < cells_.size(); ++c) {
    size_t h = hash(cells_[c].key) & mask_;
    while (table_[h] != 0) h = (h + 1) & mask_;
    table_[h] = static_cast<uint32_t>(c + 1);
  }
  set_bounds();
}

void PointGrid::set_bounds() {
  lo_x_ = lo_y_ = 0;
  hi_x_ = hi_y_ = -1;
  for (size_t c = 0; c < cells_.size(); ++c) {
    // key(): x in the high 32 bits, y in the low, each a 32-bit cell index.
    const int64_t ix = static_cast<int32_t>(static_cast<uint32_t>(cells_[c].key >> 32));
    const int64_t iy = static_cast<int32_t>(static_cast<uint32_t>(cells_[c].key));
    if (c == 0) {
      lo_x_ = hi_x_ = ix;
      lo_y_ = hi_y_ = iy;
      continue;
    }
    lo_x_ = std::min(lo_x_, ix);
    hi_x_ = std::max(hi_x_, ix);
    lo_y_ = std::min(lo_y_, iy);
    hi_y_ = std::max(hi_y_, iy);
  }
}

}  // namespace hmt::area

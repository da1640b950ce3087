#include "hmt/tsbi/cost_stack.h"

#include <algorithm>

namespace hmt::tsbi {
namespace {

// out[x] = min(out[x], in[x]) for x < n, vectorised (the two rows never
// overlap here; the compiler checks that once per call).
void min_into(uint8_t* out, const uint8_t* in, size_t n) {
  for (size_t x = 0; x < n; ++x) out[x] = std::min(out[x], in[x]);
}

}  // namespace

CostStack::CostStack(const MatchField& field, int window, int step_cells, int levels)
    : step_(step_cells), max_cost_(point_cost(MatchField::kFar, window)) {
  levels_.resize(static_cast<size_t>(levels));
  if (!field.has_obstacles()) return;  // every cost is max_cost_, at every level
  // Level 0: the field's raster and the margin around it where a cell is
  // still within reach of an obstacle (beyond, the cost saturates).
  const int pad = std::max(window, 2);
  Level& l0 = levels_[0];
  l0.x0 = field.x0() - pad;
  l0.y0 = field.y0() - pad;
  l0.w = field.width() + 2 * pad;
  l0.h = field.height() + 2 * pad;
  l0.c.resize(static_cast<size_t>(l0.w) * l0.h);
  uint8_t cost_of[MatchField::kFar + 1];
  for (int d = 0; d <= MatchField::kFar; ++d) cost_of[d] = static_cast<uint8_t>(point_cost(d, window));
  // Sizes and origin in locals (a byte store may alias them, see below).
  const int w0 = l0.w, h0 = l0.h, x00 = l0.x0, y00 = l0.y0;
  for (int y = 0; y < h0; ++y) {
    uint8_t* out = &l0.c[static_cast<size_t>(y) * static_cast<size_t>(w0)];
    for (int x = 0; x < w0; ++x) out[x] = cost_of[field.distance(x00 + x, y00 + y)];
  }
  // Level k+1 from level k: a block of 2^(k+1) steps is four blocks of 2^k
  // steps, shifted by D = 2^k steps. It reaches D cells further back than
  // level k (the blocks that start there still overlap the obstacles), so
  // its raster is level k's grown by D cells at the low ends: cell x of
  // level k+1 is the least of level k's cells x - D and x (max_cost_
  // where either lies outside level k's raster), along x and then along y
  // (the min is separable).
  const uint8_t far = static_cast<uint8_t>(max_cost_);
  for (int k = 0; k + 1 < levels; ++k) {
    const Level& a = levels_[static_cast<size_t>(k)];
    Level& b = levels_[static_cast<size_t>(k) + 1];
    const int D = (1 << k) * step_;
    b.x0 = a.x0 - D;
    b.y0 = a.y0 - D;
    b.w = a.w + D;
    b.h = a.h + D;
    // The sizes in locals: a byte store may alias any member, so loops
    // bounded by a.w or b.w would load it again after every cell, and
    // would not be vectorised (they were 85 % of this constructor's time
    // on the simulated campus, whose areas' rasters hold millions of cells).
    const size_t aw = static_cast<size_t>(a.w), bw = static_cast<size_t>(b.w);
    const int ah = a.h, bh = b.h;
    // Along x: row[x] = the least of level k's cells x - D and x, each
    // max_cost_ off level k's raster. Plain loops over whole rows (no
    // bounds test per cell): they were a tenth of the time of the Infinite
    // Corridor's late events through cost() bounds-testing every cell.
    std::vector<uint8_t> row(bw * static_cast<size_t>(ah), far);
    for (int y = 0; y < ah; ++y) {
      const uint8_t* in = &a.c[static_cast<size_t>(y) * aw];
      uint8_t* out = &row[static_cast<size_t>(y) * bw];
      std::copy(in, in + aw, out + D);
      min_into(out, in, aw);
    }
    // Along y, a row at a time: rows y - D and y of `row`.
    b.c.assign(bw * static_cast<size_t>(bh), far);
    for (int y = 0; y < bh; ++y) {
      uint8_t* out = &b.c[static_cast<size_t>(y) * bw];
      for (const int iy : {y - D, y}) {
        if (iy < 0 || iy >= ah) continue;
        min_into(out, &row[static_cast<size_t>(iy) * bw], bw);
      }
    }
  }
}

size_t CostStack::bytes() const {
  size_t n = 0;
  for (const Level& l : levels_) n += l.c.size();
  return n;
}

}  // namespace hmt::tsbi

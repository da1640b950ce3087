#include "hmt/tsbi/cost_stack.h"

namespace hmt::tsbi {

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
  for (int y = 0; y < l0.h; ++y)
    for (int x = 0; x < l0.w; ++x)
      l0.c[static_cast<size_t>(y) * l0.w + x] =
          static_cast<uint8_t>(point_cost(field.distance(l0.x0 + x, l0.y0 + y), window));
  // Level k+1 from level k: a block of 2^(k+1) steps is four blocks of 2^k
  // steps, shifted by D = 2^k steps. It reaches D cells further back than
  // level k (the blocks that start there still overlap the obstacles).
  for (int k = 0; k + 1 < levels; ++k) {
    const Level& a = levels_[static_cast<size_t>(k)];
    Level& b = levels_[static_cast<size_t>(k) + 1];
    const int D = (1 << k) * step_;
    b.x0 = a.x0 - D;
    b.y0 = a.y0 - D;
    b.w = a.w + D;
    b.h = a.h + D;
    // Along x first, then along y (the min is separable).
    std::vector<uint8_t> row(static_cast<size_t>(b.w) * a.h);
    for (int y = 0; y < a.h; ++y)
      for (int x = 0; x < b.w; ++x) {
        const int cx = b.x0 + x, cy = a.y0 + y;
        row[static_cast<size_t>(y) * b.w + x] =
            static_cast<uint8_t>(std::min(cost(k, cx, cy), cost(k, cx + D, cy)));
      }
    auto row_at = [&](int x, int iy) -> int {
      return static_cast<unsigned>(iy) < static_cast<unsigned>(a.h)
                 ? row[static_cast<size_t>(iy) * b.w + x]
                 : max_cost_;
    };
    b.c.resize(static_cast<size_t>(b.w) * b.h);
    for (int y = 0; y < b.h; ++y) {
      const int iy = b.y0 + y - a.y0;  // row of level k's raster at this y
      for (int x = 0; x < b.w; ++x)
        b.c[static_cast<size_t>(y) * b.w + x] =
            static_cast<uint8_t>(std::min(row_at(x, iy), row_at(x, iy + D)));
    }
  }
}

size_t CostStack::bytes() const {
  size_t n = 0;
  for (const Level& l : levels_) n += l.c.size();
  return n;
}

}  // namespace hmt::tsbi

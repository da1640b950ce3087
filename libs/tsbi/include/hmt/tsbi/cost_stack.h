// The per-map precomputation of the branch-and-bound search for loop-closure
// modes (bnb_matcher.h): a stack of min-filtered rasters of the search's
// point cost, in the manner of Cartographer's FastCorrelativeScanMatcher2D
// and Olson's multi-resolution matcher.
//
// The point cost is the wide search's: a point whose cell lies d cells
// (Chebyshev, MatchField) from the nearest obstacle costs min(d, reach)^2,
// reach = coarse window + 1/2 cells, as the matcher's likelihood field is
// truncated at its window. Stored times 4, the costs are the integers
// min((2d)^2, (2w + 1)^2): sums are exact, so ties are ties.
//
// Level k holds, at cell (x, y), the least level-0 cost over the cells
// (x + a s, y + b s), 0 <= a, b < 2^k, s the search's translation step in
// cells: a lower bound of a point's cost over every translation of a
// block of 2^k x 2^k lattice steps. Built once per archived map (the map
// never changes) and kept in a byte-bounded cache (transition_model.h).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "hmt/tsbi/match_field.h"

namespace hmt::tsbi {

class CostStack {
 public:
  // `window`: the matcher's coarse window (cells; the cost saturates half a
  // cell beyond the larger of it and 2); `step_cells`: the lattice's
  // translation step; `levels`: blocks of up to 2^(levels-1) steps a side.
  CostStack(const MatchField& field, int window, int step_cells, int levels);

  int levels() const { return static_cast<int>(levels_.size()); }
  int step_cells() const { return step_; }
  // The saturated cost: every point far from all obstacles.
  int max_cost() const { return max_cost_; }
  // The cost of one point in cell (cx, cy): level 0 is exact, level k the
  // least cost over the block of translations it stands for.
  int cost(int level, int cx, int cy) const {
    const Level& l = levels_[static_cast<size_t>(level)];
    const int ix = cx - l.x0, iy = cy - l.y0;
    if (static_cast<unsigned>(ix) < static_cast<unsigned>(l.w) &&
        static_cast<unsigned>(iy) < static_cast<unsigned>(l.h))
      return l.c[static_cast<size_t>(iy) * l.w + ix];
    return max_cost_;
  }
  size_t bytes() const;
  // Whether level `level` has any cell below max_cost(): then the cells
  // that do lie in [x0, x1] x [y0, y1], the level's raster.
  bool raster(int level, int* x0, int* y0, int* x1, int* y1) const {
    const Level& l = levels_[static_cast<size_t>(level)];
    *x0 = l.x0;
    *y0 = l.y0;
    *x1 = l.x0 + l.w - 1;
    *y1 = l.y0 + l.h - 1;
    return !l.c.empty();
  }

  // The level-0 cost of a cell at distance `d` from the nearest obstacle.
  static int point_cost(int d, int window) {
    const int reach2 = 2 * std::max(window, 2) + 1;  // twice the reach
    return std::min(4 * d * d, reach2 * reach2);
  }

 private:
  // A raster of costs; outside it every cost is max_cost_.
  struct Level {
    int x0 = 0, y0 = 0, w = 0, h = 0;
    std::vector<uint8_t> c;
  };
  int step_;
  int max_cost_;
  std::vector<Level> levels_;
};

}  // namespace hmt::tsbi

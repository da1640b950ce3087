#include "hmt/tsbi/bnb_matcher.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <queue>

#include "hmt/common/error.h"
#include "hmt/common/int_div.h"

namespace hmt::tsbi {

Pose2D SearchLattice::pose(int i, int j, int t) const {
  return Pose2D(center.x + i * step_xy(), center.y + j * step_xy(),
                wrap_angle(center.theta + t * step_theta));
}

double SearchLattice::distance2(int i, int j, int t) const {
  const Eigen::Vector3d e(i * step_xy(), j * step_xy(), t * step_theta);
  return e.dot(information * e);
}

bool SearchLattice::in_gate(int i, int j, int t) const { return distance2(i, j, t) <= gate; }

bool SearchLattice::block_meets_gate(int i0, int i1, int j0, int j1, int t) const {
  const Eigen::Matrix3d& M = information;
  const double sx = step_xy();
  const double th = t * step_theta;
  const double x0 = i0 * sx, x1 = i1 * sx, y0 = j0 * sx, y1 = j1 * sx;
  // q(x, y) = a x^2 + 2 b x y + c y^2 + 2 (d x + e y) + f at this heading:
  // convex, so its minimum over the block is the free minimum if that lies
  // inside, else the least of the four edges' clamped minima.
  const double a = M(0, 0), b = M(0, 1), c = M(1, 1);
  const double d = M(0, 2) * th, e = M(1, 2) * th, f = M(2, 2) * th * th;
  auto q = [&](double x, double y) {
    return a * x * x + 2 * b * x * y + c * y * y + 2 * (d * x + e * y) + f;
  };
  const double det = a * c - b * b;
  double best;
  const double xf = (b * e - c * d) / det, yf = (b * d - a * e) / det;
  if (xf >= x0 && xf <= x1 && yf >= y0 && yf <= y1) {
    best = q(xf, yf);
  } else {
    auto on_x = [&](double x) {  // edge at fixed x: minimise over y
      return q(x, std::clamp(-(b * x + e) / c, y0, y1));
    };
    auto on_y = [&](double y) {
      return q(std::clamp(-(b * y + d) / a, x0, x1), y);
    };
    best = std::min({on_x(x0), on_x(x1), on_y(y0), on_y(y1)});
  }
  return best <= gate + 1e-9 * (1.0 + gate);
}

bool SearchLattice::block_inside_gate(int i0, int i1, int j0, int j1, int t) const {
  const double m = gate - 1e-9 * (1.0 + gate);
  for (int i : {i0, i1})
    for (int j : {j0, j1})
      if (!(distance2(i, j, t) <= m)) return false;
  return true;
}

void SearchLattice::cells(const std::vector<Point2D>& pts, int t, int* cx, int* cy) const {
  const double th = center.theta + t * step_theta;
  const double cs = std::cos(th), sn = std::sin(th);
  for (size_t k = 0; k < pts.size(); ++k) {
    cx[k] = MatchField::floor_cell((center.x + cs * pts[k].x - sn * pts[k].y) / resolution);
    cy[k] = MatchField::floor_cell((center.y + sn * pts[k].x + cs * pts[k].y) / resolution);
  }
}

namespace {

// The gate and its bounding box: |e_k| <= sqrt(gate cov_kk) on each axis.
void set_gate(SearchLattice* l, double gate, const Eigen::Matrix3d& cov) {
  l->gate = gate;
  l->nx = static_cast<int>(std::sqrt(gate * cov(0, 0)) / l->step_xy());
  l->ny = static_cast<int>(std::sqrt(gate * cov(1, 1)) / l->step_xy());
  l->nt = static_cast<int>(std::min(M_PI, std::sqrt(gate * cov(2, 2))) / l->step_theta);
}

}  // namespace

SearchLattice gate_lattice(const topology::PoseGaussian& prior, double gate, double step_xy,
                           double step_theta, double resolution) {
  SearchLattice l;
  l.center = prior.mean;
  l.resolution = resolution;
  l.step_cells = std::max(1, static_cast<int>(std::lround(step_xy / resolution)));
  l.step_theta = step_theta;
  l.information = prior.cov.inverse();
  set_gate(&l, gate, prior.cov);
  return l;
}

int root_level(const SearchLattice& l, int levels) {
  int top = 0;
  while (top + 1 < levels && (1 << top) < 2 * std::max(l.nx, l.ny) + 1) ++top;
  return top;
}

namespace {

// The bounding box {x0, y0, x1, y1} of n points' cells.
using CellBox = std::array<int, 4>;
CellBox box_of(const int* cx, const int* cy, size_t n) {
  CellBox b = {cx[0], cy[0], cx[0], cy[0]};
  for (size_t k = 1; k < n; ++k) {
    b[0] = std::min(b[0], cx[k]);
    b[1] = std::min(b[1], cy[k]);
    b[2] = std::max(b[2], cx[k]);
    b[3] = std::max(b[3], cy[k]);
  }
  return b;
}

// The points' cells' box at every heading of `l`, t = -nt..nt.
std::vector<CellBox> heading_boxes(const SearchLattice& l, const std::vector<Point2D>& pts) {
  std::vector<int> cx(pts.size()), cy(pts.size());
  std::vector<CellBox> boxes;
  for (int t = -l.nt; t <= l.nt; ++t) {
    l.cells(pts, t, cx.data(), cy.data());
    boxes.push_back(box_of(cx.data(), cy.data(), pts.size()));
  }
  return boxes;
}

// The number of root blocks [-n + k b, -n + (k + 1) b - 1] (k >= 0, starts
// at most n) whose start lies in [lo, hi].
int64_t starts_within(int n, int b, int64_t lo, int64_t hi) {
  lo = std::max<int64_t>(lo, -n);
  hi = std::min<int64_t>(hi, n);
  if (lo > hi) return 0;
  // First k with -n + k b >= lo, last with -n + k b <= hi.
  const int64_t k0 = (lo + n + b - 1) / b, k1 = (hi + n) / b;
  return std::max<int64_t>(0, k1 - k0 + 1);
}

// roots_on_map() with the points' box at heading t given as
// boxes[t + boxes_nt] (a lattice of the same centre and steps, at least as
// wide: its headings include l's).
int64_t roots_on_map(const CostStack& stack, const SearchLattice& l,
                     const std::vector<CellBox>& boxes, int boxes_nt) {
  const int top = root_level(l, stack.levels());
  int rx0, ry0, rx1, ry1;
  if (!stack.raster(top, &rx0, &ry0, &rx1, &ry1)) return 0;
  const int s = l.step_cells, b = 1 << top;
  int64_t n = 0;
  for (int t = -l.nt; t <= l.nt; ++t) {
    const CellBox& p = boxes[static_cast<size_t>(t + boxes_nt)];
    // A root at (i, j) is on the map when the points' box moved by (i s,
    // j s) meets the raster (bnb_modes' test for its first pose).
    n += starts_within(l.nx, b, ceil_div(rx0 - p[2], s), floor_div(rx1 - p[0], s)) *
         starts_within(l.ny, b, ceil_div(ry0 - p[3], s), floor_div(ry1 - p[1], s));
  }
  return n;
}

}  // namespace

int64_t roots_on_map(const CostStack& stack, const SearchLattice& l,
                     const std::vector<Point2D>& pts) {
  if (pts.empty()) return 0;
  return roots_on_map(stack, l, heading_boxes(l, pts), l.nt);
}

SearchLattice budget_lattice(const CostStack& stack, const SearchLattice& lattice,
                             const std::vector<Point2D>& pts, int64_t max_roots) {
  if (pts.empty()) return lattice;
  // A narrower gate keeps the headings' indices: the boxes are computed once.
  const std::vector<CellBox> boxes = heading_boxes(lattice, pts);
  SearchLattice l = lattice;
  const Eigen::Matrix3d cov = lattice.information.inverse();
  // Ends: at a radius of a millionth the box is one pose.
  while (roots_on_map(stack, l, boxes, lattice.nt) > max_roots && l.gate > 1e-6)
    set_gate(&l, 0.8 * l.gate, cov);
  return l;
}

namespace {

// Whether lattice pose (i, j, t) is near mode m (ModeQuery's separation).
bool near(const SearchLattice& l, const ModeQuery& q, const SearchMode& m, int i, int j, int t) {
  return std::abs(i - m.i) * l.step_xy() < q.separation_xy &&
         std::abs(j - m.j) * l.step_xy() < q.separation_xy &&
         std::fabs(wrap_angle((t - m.t) * l.step_theta)) < q.separation_theta;
}

bool near_any(const SearchLattice& l, const ModeQuery& q, const std::vector<SearchMode>& modes,
              int i, int j, int t) {
  return std::any_of(modes.begin(), modes.end(),
                     [&](const SearchMode& m) { return near(l, q, m, i, j, t); });
}

// A block of 2^level x 2^level translations from (i, j) at heading t, with
// the lower bound of its poses' costs (level 0: one pose, its cost). Packed
// in 16 bytes: a wide window's search holds up to millions of them.
struct Block {
  int32_t cost;
  int32_t j, i;
  int16_t t;
  int8_t level;
  bool inside;  // wholly in the gate: its sub-blocks need no gate test
};

// The order blocks are expanded in: cost first; at equal cost a block
// before a pose (so that every pose of that cost is out before the first
// is taken), then the lattice order among poses. A strict total order, so
// the search does not depend on the heap's implementation.
bool before(const Block& a, const Block& b) {
  if (a.cost != b.cost) return a.cost < b.cost;
  if ((a.level == 0) != (b.level == 0)) return a.level != 0;
  if (a.level != b.level) return a.level > b.level;
  if (a.t != b.t) return a.t < b.t;
  if (a.j != b.j) return a.j < b.j;
  return a.i < b.i;
}

}  // namespace

std::vector<SearchMode> bnb_modes(const CostStack& stack, const SearchLattice& l,
                                  const std::vector<Point2D>& pts, const ModeQuery& query,
                                  SearchStats* stats) {
  std::vector<SearchMode> modes;
  if (pts.empty() || query.count <= 0) return modes;
  if (pts.size() > 100000 || l.nt > 32767)
    throw Error(ExitCode::kInternal, "bnb_modes: more points or headings than a block holds");
  const size_t n = pts.size();
  const int s = l.step_cells;
  const int nth = 2 * l.nt + 1;
  std::vector<int> cx(static_cast<size_t>(nth) * n), cy(cx.size());
  for (int t = -l.nt; t <= l.nt; ++t) {
    const size_t o = static_cast<size_t>(t + l.nt) * n;
    l.cells(pts, t, cx.data() + o, cy.data() + o);
  }
  // The points' cells' bounding box at each heading: a block that puts
  // every point outside the stack's raster costs the maximum for each, with
  // no lookup (the window is often much larger than the area's map).
  std::vector<CellBox> box(static_cast<size_t>(nth));
  for (size_t a = 0; a < box.size(); ++a) box[a] = box_of(cx.data() + a * n, cy.data() + a * n, n);
  std::vector<std::array<int, 4>> raster(static_cast<size_t>(stack.levels()));
  std::vector<char> has_raster(raster.size());
  for (int k = 0; k < stack.levels(); ++k)
    has_raster[static_cast<size_t>(k)] = stack.raster(k, &raster[static_cast<size_t>(k)][0],
                                                      &raster[static_cast<size_t>(k)][1],
                                                      &raster[static_cast<size_t>(k)][2],
                                                      &raster[static_cast<size_t>(k)][3]);
  const int64_t all_far = static_cast<int64_t>(n) * stack.max_cost();
  SearchStats local;
  SearchStats& st = stats ? *stats : local;
  int64_t limit = query.max_cost;  // tightened once the best mode is out
  // Whether a block puts every point outside the stack's raster (its bound
  // is then all_far, with no lookup).
  auto off_raster = [&](int level, int t, int i, int j) {
    const CellBox& b = box[static_cast<size_t>(t + l.nt)];
    const std::array<int, 4>& r = raster[static_cast<size_t>(level)];
    const int dx = i * s, dy = j * s;
    return !has_raster[static_cast<size_t>(level)] || b[2] + dx < r[0] || b[0] + dx > r[2] ||
           b[3] + dy < r[1] || b[1] + dy > r[3];
  };
  // The bound of a block that overlaps the raster; stops at the limit
  // (costs are never negative).
  auto bound = [&](int level, int t, int i, int j) {
    ++st.blocks;
    const int dx = i * s, dy = j * s;
    const size_t o = static_cast<size_t>(t + l.nt) * n;
    int64_t sum = 0;
    for (size_t k = 0; k < n; ++k) {
      sum += stack.cost(level, cx[o + k] + dx, cy[o + k] + dy);
      if (sum > limit) break;
    }
    return sum;
  };
  auto last = [](int first, int level, int end) { return std::min(first + (1 << level) - 1, end); };
  std::vector<Block> heap;
  auto cmp = [](const Block& a, const Block& b) { return before(b, a); };
  // Grown as blocks are bounded, not reserved for the budget: most searches
  // bound a few thousand blocks, and a reservation for the budget (16 MB at
  // a million blocks, per searching thread) was a fifth of the whole
  // program's peak heap on the Infinite Corridor. Growth costs a copy of at
  // most half the final size.
  // The gate tests were most of a wide window's search (37 % of the time
  // of the Infinite Corridor's costliest events): a block wholly inside the
  // gate passes that on to its sub-blocks, which then skip them.
  auto push = [&](int level, int t, int i, int j, bool inside) {
    if (st.blocks >= query.max_blocks) {
      st.stopped = true;
      return;
    }
    // Off the map and over the limit whatever the gate says: no test.
    const bool off = off_raster(level, t, i, j);
    if (off && all_far > limit) return;
    const int i1 = last(i, level, l.nx), j1 = last(j, level, l.ny);
    if (!inside) {
      if (!l.block_meets_gate(i, i1, j, j1, t)) return;
      if (level == 0 && !l.in_gate(i, j, t)) return;
      inside = level > 0 && l.block_inside_gate(i, i1, j, j1, t);
    }
    const int64_t c = off ? all_far : bound(level, t, i, j);
    if (c > limit) return;
    heap.push_back({static_cast<int32_t>(c), j, i, static_cast<int16_t>(t),
                    static_cast<int8_t>(level), inside});
    std::push_heap(heap.begin(), heap.end(), cmp);
  };
  const int top = root_level(l, stack.levels());
  for (int t = -l.nt; t <= l.nt; ++t)
    for (int j = -l.ny; j <= l.ny; j += 1 << top)
      for (int i = -l.nx; i <= l.nx; i += 1 << top) push(top, t, i, j, false);
  while (!heap.empty() && static_cast<int>(modes.size()) < query.count && !st.stopped) {
    std::pop_heap(heap.begin(), heap.end(), cmp);
    const Block b = heap.back();
    heap.pop_back();
    if (b.cost > limit) break;  // so is everything left
    if (b.level == 0) {
      ++st.poses;
      if (!near_any(l, query, modes, b.i, b.j, b.t)) {
        modes.push_back({b.cost, b.i, b.j, b.t, l.pose(b.i, b.j, b.t)});
        if (modes.size() == 1 && query.margin < limit - b.cost) limit = b.cost + query.margin;
      }
      continue;
    }
    // A block wholly near one mode holds no other mode.
    const int i1 = last(b.i, b.level, l.nx), j1 = last(b.j, b.level, l.ny);
    const bool covered = std::any_of(modes.begin(), modes.end(), [&](const SearchMode& m) {
      return near(l, query, m, b.i, b.j, b.t) && near(l, query, m, i1, j1, b.t) &&
             near(l, query, m, b.i, j1, b.t) && near(l, query, m, i1, b.j, b.t);
    });
    if (covered) continue;
    const int h = 1 << (b.level - 1);
    for (int dj = 0; dj <= h; dj += h)
      for (int di = 0; di <= h; di += h)
        if (b.i + di <= l.nx && b.j + dj <= l.ny)
          push(b.level - 1, b.t, b.i + di, b.j + dj, b.inside);
  }
  return modes;
}

std::vector<SearchMode> exhaustive_modes(const MatchField& field, int window,
                                         const SearchLattice& l,
                                         const std::vector<Point2D>& pts,
                                         const ModeQuery& query) {
  const size_t n = pts.size();
  const int s = l.step_cells;
  std::vector<SearchMode> all;
  std::vector<int> cx(n), cy(n);
  for (int t = -l.nt; t <= l.nt; ++t) {
    l.cells(pts, t, cx.data(), cy.data());
    for (int j = -l.ny; j <= l.ny; ++j)
      for (int i = -l.nx; i <= l.nx; ++i) {
        if (!l.in_gate(i, j, t)) continue;
        int64_t cost = 0;
        for (size_t k = 0; k < n; ++k)
          cost += CostStack::point_cost(field.distance(cx[k] + i * s, cy[k] + j * s), window);
        if (cost <= query.max_cost) all.push_back({cost, i, j, t, l.pose(i, j, t)});
      }
  }
  std::stable_sort(all.begin(), all.end(),
                   [](const SearchMode& a, const SearchMode& b) { return a.cost < b.cost; });
  std::vector<SearchMode> modes;
  for (const SearchMode& m : all) {
    if (static_cast<int>(modes.size()) >= query.count) break;
    if (!modes.empty() && m.cost - modes[0].cost > query.margin) break;
    if (!near_any(l, query, modes, m.i, m.j, m.t)) modes.push_back(m);
  }
  return modes;
}

}  // namespace hmt::tsbi

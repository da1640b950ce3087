#include "hmt/tsbi/match_field.h"

#include <Eigen/Dense>
#include <algorithm>
#include <climits>
#include <cmath>

namespace hmt::tsbi {
namespace {

// Calls f(x, y) for every cell of `map` at or above `occupied`.
template <class F>
void for_each_obstacle(const grid::OccupancyGrid& map, grid::LogOdds occupied, F&& f) {
  using grid::kTileBits;
  using grid::kTileSize;
  grid::CellIndex lo, hi;
  if (!map.bounds(&lo, &hi)) return;
  for (int ty = lo.y >> kTileBits; ty <= hi.y >> kTileBits; ++ty)
    for (int tx = lo.x >> kTileBits; tx <= hi.x >> kTileBits; ++tx) {
      const grid::Tile* t = map.tile(tx, ty);
      if (!t) continue;
      for (int j = 0; j < kTileSize; ++j)
        for (int i = 0; i < kTileSize; ++i)
          if (t->logodds[static_cast<size_t>((j << kTileBits) | i)] >= occupied)
            f(tx * kTileSize + i, ty * kTileSize + j);
    }
}

}  // namespace

MatchField::MatchField(const grid::OccupancyGrid& map, grid::LogOdds occupied)
    : resolution_(map.resolution()), inv_resolution_(1.0 / map.resolution()) {
  int x0 = INT_MAX, y0 = INT_MAX, x1 = INT_MIN, y1 = INT_MIN;
  for_each_obstacle(map, occupied, [&](int x, int y) {
    x0 = std::min(x0, x);
    y0 = std::min(y0, y);
    x1 = std::max(x1, x);
    y1 = std::max(y1, y);
  });
  if (x0 > x1) return;  // no obstacle: nothing can ever match
  x0_ = x0;
  y0_ = y0;
  w_ = x1 - x0 + 1;
  h_ = y1 - y0 + 1;
  d_.assign(static_cast<size_t>(w_) * h_, kFar);
  for_each_obstacle(map, occupied, [&](int x, int y) {
    d_[static_cast<size_t>(y - y0_) * w_ + (x - x0_)] = 0;
  });
  // Two-pass chessboard distance transform: exact for the Chebyshev metric
  // on a rectangle (each pass propagates from the 4 neighbours it has seen).
  // Row by row: the three neighbours in the row already passed first (a
  // loop without dependencies between cells), then the one before in this
  // row (the same minima as relaxing the four in turn, cell by cell, with
  // no bounds test per neighbour: fields of 100 m areas have millions of
  // cells).
  //
  // The width in a local: a byte store may alias any member, so loops
  // bounded by w_ would load it again after every cell and would not be
  // vectorised.
  const int W = w_;
  std::vector<uint8_t> t(static_cast<size_t>(W));
  auto pass = [&t, W](uint8_t* row, const uint8_t* seen, int dir) {
    if (seen) {
      uint8_t* out = t.data();
      // m + 1 <= 256 and row[x] <= 255: the least fits a byte.
      auto relax = [&](int x, int m) {
        out[x] = static_cast<uint8_t>(std::min<int>(row[x], m + 1));
      };
      if (W == 1) {
        relax(0, seen[0]);
      } else {
        relax(0, std::min(seen[0], seen[1]));
        for (int x = 1; x + 1 < W; ++x)
          relax(x, std::min(std::min(seen[x - 1], seen[x]), seen[x + 1]));
        relax(W - 1, std::min(seen[W - 2], seen[W - 1]));
      }
      std::copy(t.begin(), t.end(), row);
    }
    if (dir > 0) {
      for (int x = 1; x < W; ++x) row[x] = static_cast<uint8_t>(std::min<int>(row[x], row[x - 1] + 1));
    } else {
      for (int x = W - 2; x >= 0; --x) row[x] = static_cast<uint8_t>(std::min<int>(row[x], row[x + 1] + 1));
    }
  };
  uint8_t* d = d_.data();
  const size_t w = static_cast<size_t>(W);
  const int H = h_;
  for (int y = 0; y < H; ++y) pass(d + y * w, y > 0 ? d + (y - 1) * w : nullptr, +1);
  for (int y = H - 1; y >= 0; --y) pass(d + y * w, y + 1 < H ? d + (y + 1) * w : nullptr, -1);
}

int MatchField::outside_distance(int ix, int iy) const {
  if (d_.empty()) return kFar;
  const int dx = ix < 0 ? -ix : std::max(0, ix - w_ + 1);
  const int dy = iy < 0 ? -iy : std::max(0, iy - h_ + 1);
  return std::min(kFar, std::max(dx, dy));
}

namespace {

// A box of poses around the prior mean: offsets c +- h (x, y, theta).
struct Box {
  Eigen::Vector3d c, h;
};

}  // namespace

bool may_reach_ratio(const MatchField& field, const std::vector<Point2D>& points,
                     const topology::PoseGaussian& prior, double gate, double min_ratio,
                     int window, int max_boxes) {
  const size_t n = points.size();
  if (n == 0 || !field.has_obstacles()) return false;
  const double res = field.resolution();
  std::vector<double> range(n);
  double r_sum = 0.0;
  for (size_t i = 0; i < n; ++i) {
    range[i] = std::hypot(points[i].x, points[i].y);
    r_sum += range[i];
  }
  const double r_mean = r_sum / static_cast<double>(n);
  // The same test as the ratio gate it stands for: matched / n >= min_ratio.
  // It only grows with the count, so the least count that passes (n + 1:
  // none does) is found once with it and the counting below compares
  // integers, not a division per point.
  size_t need = 0;
  while (need <= n && static_cast<double>(need) / static_cast<double>(n) < min_ratio) ++need;
  auto passes = [need](size_t count) { return count >= need; };
  // An upper bound on the points matched anywhere in the box; counting
  // stops as soon as the box is known to pass or to fail.
  auto bound = [&](const Box& b) {
    const double th = prior.mean.theta + b.c.z();
    const double cs = std::cos(th), sn = std::sin(th);
    const double px = prior.mean.x + b.c.x(), py = prior.mean.y + b.c.y();
    const double dxy = std::hypot(b.h.x(), b.h.y());
    size_t count = 0;
    for (size_t i = 0; i < n; ++i) {
      const Point2D& p = points[i];
      // d <= window + ceil(x) for integers d, window is d - window - 1 < x.
      const double x = (dxy + range[i] * b.h.z()) / res;
      if (field.distance_at(px + cs * p.x - sn * p.y, py + sn * p.x + cs * p.y) - window - 1 < x) {
        if (passes(++count)) break;
      } else if (!passes(count + (n - 1 - i))) {
        break;
      }
    }
    return count;
  };
  // A box lies outside the gate if even its nearest point does:
  // |L^-1 (c + d)| >= |L^-1 c| - sum_j h_j |column j of L^-1|.
  const Eigen::Matrix3d L_inv = Eigen::Matrix3d(prior.cov.llt().matrixL()).inverse();
  const Eigen::Vector3d col_norms = L_inv.colwise().norm().transpose();
  auto outside_gate = [&](const Box& b) {
    const double m = (L_inv * b.c).norm() - col_norms.dot(b.h);
    return m > 0 && m * m > gate;
  };
  // Small enough to stop: the pose moves a point at the mean range by two
  // cells at most. (Any rule is sound here: stopping only means "maybe";
  // finer boxes would rarely turn a maybe into a proof, at many boxes' cost.)
  auto smallest = [&](const Box& b) {
    return std::hypot(b.h.x(), b.h.y()) + r_mean * b.h.z() <= 2 * res;
  };

  Box root{Eigen::Vector3d::Zero(),
           Eigen::Vector3d(std::sqrt(gate * prior.cov(0, 0)), std::sqrt(gate * prior.cov(1, 1)),
                           std::min(M_PI, std::sqrt(gate * prior.cov(2, 2))))};
  if (!passes(bound(root))) return false;
  // Depth first, the child nearest the prior mean first: when the area is
  // the right one, a box that passes is usually found there quickly.
  std::vector<Box> stack{root};
  int boxes = 1;
  while (!stack.empty()) {
    const Box b = stack.back();
    stack.pop_back();
    if (smallest(b)) return true;
    std::vector<Box> children;
    const Eigen::Vector3d q = 0.5 * b.h;
    if (std::hypot(b.h.x(), b.h.y()) >= r_mean * b.h.z()) {
      for (int sx = -1; sx <= 1; sx += 2)
        for (int sy = -1; sy <= 1; sy += 2)
          children.push_back({b.c + Eigen::Vector3d(sx * q.x(), sy * q.y(), 0.0),
                              Eigen::Vector3d(q.x(), q.y(), b.h.z())});
    } else {
      for (int st = -1; st <= 1; st += 2)
        children.push_back({b.c + Eigen::Vector3d(0.0, 0.0, st * q.z()),
                            Eigen::Vector3d(b.h.x(), b.h.y(), q.z())});
    }
    std::vector<std::pair<double, Box>> alive;
    for (const Box& c : children) {
      if (outside_gate(c)) continue;
      if (++boxes > max_boxes) return true;  // no proof within the budget
      if (passes(bound(c))) alive.emplace_back((L_inv * c.c).squaredNorm(), c);
    }
    std::stable_sort(alive.begin(), alive.end(),
                     [](const auto& a, const auto& b) { return a.first > b.first; });
    for (const auto& a : alive) stack.push_back(a.second);
  }
  return false;
}

}  // namespace hmt::tsbi

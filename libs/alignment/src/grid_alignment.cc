#include "hmt/alignment/grid_alignment.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <unordered_map>

#include "hmt/alignment/icp.h"

namespace hmt::alignment {
namespace {

using grid::Cell;
using grid::CellIndex;
using grid::OccupancyGrid;

// A cell is a point when its log-odds exceed logit(p) (scaled) and it has
// been hit often enough for its hit mean to mean something.
struct PointTest {
  int threshold;
  int min_hits;
  explicit PointTest(const AlignmentOptions& opt)
      : threshold(static_cast<int>(std::lround(
            std::log(opt.occupied_probability / (1.0 - opt.occupied_probability)) *
            grid::kLogOddsScale))),
        min_hits(opt.min_hits) {}
  bool operator()(const Cell& c) const {
    return c.logodds > threshold && c.hits >= min_hits;
  }
};

std::string format(double v, int precision = 3) {
  std::ostringstream os;
  os.precision(precision);
  os << v;
  return os.str();
}

// The fixed grid as a spatial index of its points: a query visits the cells
// around it (the grid is already the bucket structure a k-d tree would
// rebuild), and the wall normal of each point is computed once, on demand.
class FixedIndex {
 public:
  FixedIndex(const OccupancyGrid& g, const AlignmentOptions& opt)
      : g_(g), is_point_(opt), normal_radius_(opt.normal_radius) {}

  // The nearest point within `radius` of (x, y): false if none. Ties go to
  // the first cell visited (row by row), so the answer is deterministic.
  bool nearest(double x, double y, double radius, Point2D* q, CellIndex* at) const {
    const CellIndex lo = g_.cell_of(x - radius, y - radius);
    const CellIndex hi = g_.cell_of(x + radius, y + radius);
    double best = radius * radius;
    bool found = false;
    for (int cy = lo.y; cy <= hi.y; ++cy)
      for (int cx = lo.x; cx <= hi.x; ++cx) {
        const CellIndex c{cx, cy};
        const Cell cell = g_.cell(c);  // unknown space: all zero, no point
        if (!is_point_(cell)) continue;
        const Point2D m = g_.hit_mean(c, cell);
        const double d2 = (m.x - x) * (m.x - x) + (m.y - y) * (m.y - y);
        if (d2 <= best) {
          if (found && d2 == best) continue;
          best = d2;
          *q = m;
          *at = c;
          found = true;
        }
      }
    return found;
  }

  // Whether the fixed grid has observed anything (a cell with non-zero
  // log-odds: free or occupied) within `radius` of (x, y).
  bool observed(double x, double y, double radius) const {
    const CellIndex lo = g_.cell_of(x - radius, y - radius);
    const CellIndex hi = g_.cell_of(x + radius, y + radius);
    for (int cy = lo.y; cy <= hi.y; ++cy)
      for (int cx = lo.x; cx <= hi.x; ++cx)
        if (g_.cell(CellIndex{cx, cy}).logodds != 0) return true;
    return false;
  }

  // The local shape around the point of cell `c`, from the points within
  // normal_radius: a wall (their scatter is thin, smallest over largest
  // eigenvalue below 0.1; `n` is the unit normal), a corner (at least 3
  // points, not thin: corners, pillars, clutter) or isolated (fewer than 3:
  // a stray hit, or the sparse hits of a wall seen at a grazing angle, whose
  // pairing with the other grid's stray hits is arbitrary).
  enum class Shape { kWall, kCorner, kIsolated };
  Shape shape(CellIndex c, Eigen::Vector2d* n) {
    const uint64_t key = (static_cast<uint64_t>(static_cast<uint32_t>(c.x)) << 32) |
                         static_cast<uint32_t>(c.y);
    auto it = shapes_.find(key);
    if (it == shapes_.end()) it = shapes_.emplace(key, compute_shape(c)).first;
    *n = it->second.n;
    return it->second.shape;
  }

 private:
  struct Local {
    Shape shape = Shape::kIsolated;
    Eigen::Vector2d n = Eigen::Vector2d::Zero();
  };

  Local compute_shape(CellIndex c) const {
    const Point2D q = g_.hit_mean(c, g_.cell(c));
    const double r = normal_radius_;
    const CellIndex lo = g_.cell_of(q.x - r, q.y - r);
    const CellIndex hi = g_.cell_of(q.x + r, q.y + r);
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    Eigen::Matrix2d sq = Eigen::Matrix2d::Zero();
    int n = 0;
    for (int cy = lo.y; cy <= hi.y; ++cy)
      for (int cx = lo.x; cx <= hi.x; ++cx) {
        const CellIndex k{cx, cy};
        const Cell cell = g_.cell(k);
        if (!is_point_(cell)) continue;
        const Point2D m = g_.hit_mean(k, cell);
        const Eigen::Vector2d d(m.x - q.x, m.y - q.y);  // centred on q: no cancellation
        if (d.squaredNorm() > r * r) continue;
        sum += d;
        sq += d * d.transpose();
        ++n;
      }
    Local out;
    if (n < 3) return out;
    const Eigen::Vector2d mean = sum / n;
    const Eigen::Matrix2d cov = sq / n - mean * mean.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
    const double lmin = es.eigenvalues()(0), lmax = es.eigenvalues()(1);
    out.shape = Shape::kCorner;
    if (lmax > 0 && lmin < 0.1 * lmax) {
      out.shape = Shape::kWall;
      out.n = es.eigenvectors().col(0).normalized();
    }
    return out;
  }

  const OccupancyGrid& g_;
  PointTest is_point_;
  double normal_radius_;
  std::unordered_map<uint64_t, Local> shapes_;  // lookup only: order-free
};

// The normal equations of the pairs at `pose` (additive perturbation of
// (x, y, theta), the parameterisation of PoseGaussian::cov).
struct NormalEquations {
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();  // sum w J^T J
  Eigen::Vector3d g = Eigen::Vector3d::Zero();  // sum w J^T r
  double weighted_sq = 0.0;                     // sum w r^2
  double sq = 0.0;                              // sum |r|^2 (unweighted)
  int components = 0;                           // residual rows
  int pairs = 0;           // moving points with a fixed point in reach
  int overlap = 0;         // moving points where the fixed grid has observed
  int residual_pairs = 0;  // ... of which on a wall or a corner (not isolated)
};

NormalEquations build_normal_equations(const std::vector<Point2D>& moving,
                                       FixedIndex& fixed, const Pose2D& pose,
                                       const AlignmentOptions& opt) {
  NormalEquations ne;
  const double c = std::cos(pose.theta), s = std::sin(pose.theta);
  const double inv_scale2 = 1.0 / (opt.robust_scale * opt.robust_scale);
  for (const Point2D& p : moving) {
    const Point2D x = pose.transform(p);
    Point2D q;
    CellIndex at;
    if (!fixed.nearest(x.x, x.y, opt.match_distance, &q, &at)) {
      if (fixed.observed(x.x, x.y, opt.match_distance)) ++ne.overlap;
      continue;
    }
    ++ne.pairs;
    ++ne.overlap;
    // d(R p)/d theta
    const Eigen::Vector2d dr(-s * p.x - c * p.y, c * p.x - s * p.y);
    const Eigen::Vector2d e(x.x - q.x, x.y - q.y);
    Eigen::Vector2d n;
    const FixedIndex::Shape shape = fixed.shape(at, &n);
    if (shape == FixedIndex::Shape::kIsolated) continue;  // paired, no residual
    if (shape == FixedIndex::Shape::kWall) {
      const double r = n.dot(e);
      const Eigen::Vector3d J(n.x(), n.y(), n.dot(dr));
      const double w = 1.0 / (1.0 + r * r * inv_scale2);
      ne.H += w * J * J.transpose();
      ne.g += w * J * r;
      ne.weighted_sq += w * r * r;
      ne.sq += r * r;
      ne.components += 1;
      ++ne.residual_pairs;
    } else {
      Eigen::Matrix<double, 2, 3> J;
      J << 1, 0, dr.x(), 0, 1, dr.y();
      const double w = 1.0 / (1.0 + e.squaredNorm() * inv_scale2);
      ne.H += w * J.transpose() * J;
      ne.g += w * J.transpose() * e;
      ne.weighted_sq += w * e.squaredNorm();
      ne.sq += e.squaredNorm();
      ne.components += 2;
      ++ne.residual_pairs;
    }
  }
  return ne;
}

// H^-1 restricted to its well-determined directions (eigenvalues above
// 1e-12 of the largest); `rank_ok` false when some direction was dropped.
Eigen::Matrix3d safe_inverse(const Eigen::Matrix3d& H, bool* rank_ok) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(H);
  const Eigen::Vector3d l = es.eigenvalues();
  const double lmax = l(2);
  Eigen::Vector3d inv = Eigen::Vector3d::Zero();
  *rank_ok = lmax > 0;
  for (int i = 0; i < 3; ++i) {
    if (lmax > 0 && l(i) > 1e-12 * lmax)
      inv(i) = 1.0 / l(i);
    else
      *rank_ok = false;
  }
  return es.eigenvectors() * inv.asDiagonal() * es.eigenvectors().transpose();
}

// Smallest over largest eigenvalue of the information on (x, y) with the
// rotation marginalised out (Schur complement of H's angle entry): 1 when
// every direction of travel is equally well fixed, 0 along a single wall.
double translation_information_ratio(const Eigen::Matrix3d& H) {
  if (!(H(2, 2) > 0)) return 0.0;
  const Eigen::Matrix2d Ht = H.topLeftCorner<2, 2>() -
                             H.topRightCorner<2, 1>() * H.bottomLeftCorner<1, 2>() / H(2, 2);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(Ht);
  const double lmin = es.eigenvalues()(0), lmax = es.eigenvalues()(1);
  return lmax > 0 ? std::max(0.0, lmin / lmax) : 0.0;
}

}  // namespace

std::vector<Point2D> occupied_points(const grid::OccupancyGrid& grid,
                                     const AlignmentOptions& opt) {
  std::vector<Point2D> out;
  CellIndex lo, hi;
  if (!grid.bounds(&lo, &hi)) return out;
  const PointTest is_point(opt);
  // Tile row by tile row, each tile's cells row by row: one tile fetch per
  // 32 x 32 cells.
  for (int ty = lo.y >> grid::kTileBits; ty <= (hi.y >> grid::kTileBits); ++ty)
    for (int tx = lo.x >> grid::kTileBits; tx <= (hi.x >> grid::kTileBits); ++tx) {
      const grid::Tile* t = grid.tile(tx, ty);
      if (!t) continue;
      for (int j = 0; j < grid::kTileSize; ++j)
        for (int i = 0; i < grid::kTileSize; ++i) {
          // Tile indices are negative left of and below the origin: multiply
          // (a left shift of a negative int is undefined in C++17).
          const CellIndex c{tx * grid::kTileSize + i, ty * grid::kTileSize + j};
          const Cell cell = t->cell(OccupancyGrid::index_in_tile(c));
          if (is_point(cell)) out.push_back(grid.hit_mean(c, cell));
        }
    }
  return out;
}

AlignmentResult align_grids(const grid::OccupancyGrid& moving,
                            const grid::OccupancyGrid& fixed,
                            const topology::PoseGaussian& initial,
                            const AlignmentOptions& opt) {
  topology::require_positive_definite(initial.cov, "align_grids: initial guess");
  AlignmentResult res;
  res.pose = initial;

  const std::vector<Point2D> mpts = occupied_points(moving, opt);
  const std::vector<Point2D> fpts = occupied_points(fixed, opt);
  res.moving_points = static_cast<int>(mpts.size());
  res.fixed_points = static_cast<int>(fpts.size());
  if (res.moving_points < opt.min_points || res.fixed_points < opt.min_points) {
    res.reason = "too few points: moving grid " + std::to_string(mpts.size()) +
                 ", fixed grid " + std::to_string(fpts.size()) + " (min " +
                 std::to_string(opt.min_points) + ")";
    return res;
  }

  // Coarse to fine: classic ICP.
  const IcpResult icp = icp_register(mpts, fpts, initial.mean, opt);
  Pose2D pose = icp.pose;
  res.iterations = icp.iterations;
  res.pose.mean = pose;

  // Fine: robust Gauss-Newton, point-to-line on walls.
  FixedIndex index(fixed, opt);
  for (int it = 0; it < opt.refine_iterations; ++it) {
    const NormalEquations ne = build_normal_equations(mpts, index, pose, opt);
    if (ne.residual_pairs < opt.min_points) break;  // reported below
    bool full_rank = false;
    const Eigen::Vector3d step = -safe_inverse(ne.H, &full_rank) * ne.g;
    pose = {pose.x + step(0), pose.y + step(1), wrap_angle(pose.theta + step(2))};
    ++res.iterations;
    if (std::abs(step(0)) < 1e-7 && std::abs(step(1)) < 1e-7 &&
        std::abs(step(2)) < 1e-8)
      break;
  }
  res.pose.mean = pose;

  // Statistics and covariance at the solution.
  const NormalEquations ne = build_normal_equations(mpts, index, pose, opt);
  res.overlap_points = ne.overlap;
  res.inlier_ratio =
      ne.overlap > 0 ? static_cast<double>(ne.pairs) / static_cast<double>(ne.overlap) : 0.0;
  res.rmse = ne.residual_pairs > 0 ? std::sqrt(ne.sq / ne.residual_pairs) : 0.0;
  if (ne.residual_pairs < opt.min_points || ne.components <= 3) {
    res.reason = "too few matches: " + std::to_string(ne.residual_pairs) +
                 " moving points have a fixed wall or corner point within " +
                 format(opt.match_distance) + " m (min " +
                 std::to_string(opt.min_points) + ")";
    return res;
  }
  if (res.inlier_ratio < opt.min_inlier_ratio) {
    res.reason = "inlier ratio " + format(res.inlier_ratio) + " below " +
                 format(opt.min_inlier_ratio);
    return res;
  }
  bool full_rank = false;
  const Eigen::Matrix3d Hinv = safe_inverse(ne.H, &full_rank);
  const double sigma2 = ne.weighted_sq / (ne.components - 3);
  Eigen::Matrix3d cov = opt.covariance_inflation * sigma2 * Hinv;
  cov = 0.5 * (cov + cov.transpose()).eval();
  cov.diagonal() += Eigen::Vector3d(opt.sigma_floor_xy * opt.sigma_floor_xy,
                                    opt.sigma_floor_xy * opt.sigma_floor_xy,
                                    opt.sigma_floor_theta * opt.sigma_floor_theta);
  res.pose.cov = cov;
  res.information_ratio = translation_information_ratio(ne.H);
  if (!full_rank) {
    res.reason = "ill-conditioned: the matched points do not constrain every "
                 "direction of the pose (a single wall or corridor?)";
    return res;
  }
  if (res.information_ratio < opt.min_information_ratio) {
    res.reason = "ill-conditioned: translation information ratio " +
                 format(res.information_ratio) + " below " +
                 format(opt.min_information_ratio) +
                 " (the walls matched are (nearly) parallel: a single wall or a "
                 "featureless corridor)";
    return res;
  }
  const double sx = std::sqrt(cov(0, 0)), sy = std::sqrt(cov(1, 1)),
               st = std::sqrt(cov(2, 2));
  if (sx > opt.max_sigma_xy || sy > opt.max_sigma_xy || st > opt.max_sigma_theta) {
    res.reason = "ill-conditioned: standard deviations (" + format(sx) + " m, " +
                 format(sy) + " m, " + format(st) + " rad) above (" +
                 format(opt.max_sigma_xy) + " m, " + format(opt.max_sigma_theta) +
                 " rad)";
    return res;
  }
  if (!topology::is_positive_definite(cov)) {
    res.reason = "covariance is not positive definite";
    return res;
  }

  // The gate: the refined pose must be a plausible outcome of the guess.
  const Eigen::Vector3d d = topology::difference(pose, initial.mean);
  const Eigen::Matrix3d S = initial.cov + cov;
  const double d2 = d.dot(S.ldlt().solve(d));
  if (!(d2 <= opt.gate_chi2)) {
    res.reason = "moved implausibly far from the initial guess: (" + format(d(0)) +
                 " m, " + format(d(1)) + " m, " + format(d(2)) +
                 " rad), squared Mahalanobis distance " + format(d2) +
                 " above the gate " + format(opt.gate_chi2);
    return res;
  }
  res.ok = true;
  return res;
}

}  // namespace hmt::alignment

#include "hmt/metric_slam/scan_matcher.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "hmt/common/error.h"
#include "hmt/common/pose_gaussian.h"
#include "match_window.h"

namespace hmt::metric_slam {
namespace {

// The likelihood field summed over a scan's beams. The field is truncated at
// the window's reach: a beam with no obstacle in the window costs as much
// as one at the window's edge. score() and normal_equations() both sum
// through it, so Gauss-Newton's scores are score()'s to the bit.
class FieldSum {
 public:
  FieldSum() = default;
  FieldSum(double resolution, int window)
      : max_d2_((window + 0.5) * (window + 0.5) * resolution * resolution) {}
  void add(double d2) {
    sum_d2_ += std::min(d2, max_d2_);
    ++matched_;
  }
  int matched() const { return matched_; }
  // The log-likelihood of the first `beams` beams, those added among them
  // matched. Over the whole scan it is the score; after part of it, the
  // best the whole scan can still reach (the rest may cost nothing), never
  // above the score in floating point either (sums of non-negative terms
  // only grow).
  double bound(size_t beams, double inv_2sigma2) const {
    return -(sum_d2_ + (static_cast<double>(beams) - matched_) * max_d2_) * inv_2sigma2;
  }
  MatchScore score(size_t beams, double inv_2sigma2) const {
    MatchScore out;
    out.matched = matched_;
    out.log_likelihood = bound(beams, inv_2sigma2);
    return out;
  }

 private:
  double max_d2_ = 0.0;
  double sum_d2_ = 0.0;
  int matched_ = 0;
};

// How far from a beam's end point a search window of `window` cells finds
// obstacles: to the edge of its outer cells, (window + 0.5) cells.
double window_reach(int window, double resolution) { return (window + 0.5) * resolution; }

// A cell's two coordinates as one integer, to compare cells in one step.
uint64_t cell_key(grid::CellIndex c) {
  return static_cast<uint64_t>(static_cast<uint32_t>(c.x)) << 32 | static_cast<uint32_t>(c.y);
}

}  // namespace

void MatcherOptions::load(Config& cfg, const std::string& s) {
  // max_range: a number, or "auto" (from the log's ranges, matching_range.h).
  cfg.get_double_or_auto(s, "max_range", &max_range, &range_from_scans);
  beam_skip = cfg.get_int(s, "beam_skip", beam_skip);
  window = cfg.get_int(s, "window", window);
  sigma = cfg.get_double(s, "sigma", sigma);
  occupied_probability = cfg.get_double(s, "occupied_probability", occupied_probability);
  linear_step = cfg.get_double(s, "linear_step", linear_step);
  angular_step = cfg.get_double(s, "angular_step", angular_step);
  refinements = cfg.get_int(s, "refinements", refinements);
  min_match_ratio = cfg.get_double(s, "min_match_ratio", min_match_ratio);
  coarse_beams = cfg.get_int(s, "coarse_beams", coarse_beams);
  coarse_window = cfg.get_int(s, "coarse_window", coarse_window);
  gauss_newton_iterations = cfg.get_int(s, "gauss_newton_iterations", gauss_newton_iterations);
  require(max_range > 0, s, "max_range", "> 0");
  require(beam_skip >= 0, s, "beam_skip", ">= 0");
  require(window >= 0 && window <= kMaxWindow, s, "window", "in [0, 5]");
  require(sigma > 0, s, "sigma", "> 0");
  // Above 0.998 the log-odds threshold would not fit the grid's one byte.
  require(occupied_probability > 0.5 && occupied_probability <= 0.998, s,
          "occupied_probability", "in (0.5, 0.998]");
  require(linear_step > 0, s, "linear_step", "> 0");
  require(angular_step > 0, s, "angular_step", "> 0");
  require(refinements >= 0 && refinements <= 20, s, "refinements", "in [0, 20]");
  require(coarse_beams >= 0, s, "coarse_beams", ">= 0 (0: all beams)");
  require(coarse_window >= 0 && coarse_window <= kMaxWindow, s, "coarse_window", "in [0, 5]");
  require(gauss_newton_iterations >= 0 && gauss_newton_iterations <= 50, s,
          "gauss_newton_iterations", "in [0, 50]");
  require(min_match_ratio >= 0 && min_match_ratio <= 1, s, "min_match_ratio",
          "in [0, 1]");
}

MatchScan::MatchScan(ScanPoints points, const MatcherOptions& opt)
    : points_(std::move(points)),
      coarse_(spread_subset(points_, opt.coarse_beams)),
      far_(far_range(points_)) {}

ScanMatcher::ScanMatcher(const MatcherOptions& opt) : opt_(opt) {
  occ_threshold_ = grid::scaled_logit(opt.occupied_probability);
  inv_2sigma2_ = 1.0 / (2.0 * opt.sigma * opt.sigma);
}

double ScanMatcher::unmatched_beam_cost(double resolution) const {
  // What the score charges one beam that finds no obstacle.
  return -FieldSum(resolution, opt_.window).bound(1, inv_2sigma2_);
}

template <class F>
void ScanMatcher::for_each_match(const grid::OccupancyGrid& map, const Pose2D& pose,
                                 const ScanPoints& scan, int w, F&& f) const {
  // The window radius as a compile-time constant: the window loops unroll
  // into straight code.
  switch (w) {
    case 0: return for_each_match_in<0>(map, pose, scan, f);
    case 1: return for_each_match_in<1>(map, pose, scan, f);
    case 2: return for_each_match_in<2>(map, pose, scan, f);
    case 3: return for_each_match_in<3>(map, pose, scan, f);
    case 4: return for_each_match_in<4>(map, pose, scan, f);
    case 5: return for_each_match_in<5>(map, pose, scan, f);
  }
  throw Error(ExitCode::kInternal, "scan matcher: window outside [0, 5]");
}

template <int W, class F>
void ScanMatcher::for_each_match_in(const grid::OccupancyGrid& map, const Pose2D& pose,
                                    const ScanPoints& scan, F& f) const {
  static_assert(W >= 0 && W <= kMaxWindow);
  const double c = std::cos(pose.theta), s = std::sin(pose.theta);
  const size_t n = scan.hit.size();
  for (size_t i = 0; i < n; ++i) {
    const Point2D& p = scan.hit[i];
    const Point2D& q = scan.free[i];
    const double hx = pose.x + c * p.x - s * p.y, hy = pose.y + s * p.x + c * p.y;
    const double fx = pose.x + c * q.x - s * q.y, fy = pose.y + s * q.x + c * q.y;
    const grid::CellIndex hc = map.cell_of(hx, hy), fc = map.cell_of(fx, fy);
    double best = std::numeric_limits<double>::infinity();
    double bx = 0, by = 0;
    // The nearest hit mean (the first one wins a tie).
    for_each_obstacle<W>(map, hc, fc, occ_threshold_, [&](double mx, double my) {
      const double d2 = (hx - mx) * (hx - mx) + (hy - my) * (hy - my);
      if (d2 < best) {
        best = d2;
        bx = mx;
        by = my;
      }
    });
    if (best < std::numeric_limits<double>::infinity() && !f(i, hx, hy, best, Point2D{bx, by}))
      return;
  }
}

MatchScore ScanMatcher::score(const grid::OccupancyGrid& map, const Pose2D& pose,
                              const ScanPoints& scan) const {
  return score(map, pose, scan, opt_.window, -std::numeric_limits<double>::infinity());
}

MatchScore ScanMatcher::score(const grid::OccupancyGrid& map, const Pose2D& pose,
                              const ScanPoints& scan, int w, double limit) const {
  FieldSum sum(map.resolution(), w);
  bool cut = false;
  for_each_match(map, pose, scan, w, [&](size_t i, double, double, double d2, const Point2D&) {
    sum.add(d2);
    cut = sum.bound(i + 1, inv_2sigma2_) <= limit;
    return !cut;
  });
  if (!cut) return sum.score(scan.hit.size(), inv_2sigma2_);
  MatchScore out;  // cannot beat `limit`: the bound, itself at or below it
  out.log_likelihood = std::numeric_limits<double>::lowest();
  return out;
}

void ScanMatcher::score_same_heading(const grid::OccupancyGrid& map, const Pose2D* poses,
                                     size_t n, const ScanPoints& scan, MatchScore* out) const {
  if (n == 0) return;
  if (n > kMaxSameHeading)
    throw Error(ExitCode::kInternal, "score_same_heading: more than 9 poses");
  for (size_t k = 1; k < n; ++k)
    if (poses[k].theta != poses[0].theta)
      throw Error(ExitCode::kInternal, "score_same_heading: poses of different headings");
  switch (opt_.window) {
    case 0: return score_same_heading_in<0>(map, poses, n, scan, out);
    case 1: return score_same_heading_in<1>(map, poses, n, scan, out);
    case 2: return score_same_heading_in<2>(map, poses, n, scan, out);
    case 3: return score_same_heading_in<3>(map, poses, n, scan, out);
    case 4: return score_same_heading_in<4>(map, poses, n, scan, out);
    case 5: return score_same_heading_in<5>(map, poses, n, scan, out);
  }
  throw Error(ExitCode::kInternal, "scan matcher: window outside [0, 5]");
}

template <int W>
void ScanMatcher::score_same_heading_in(const grid::OccupancyGrid& map, const Pose2D* poses,
                                        size_t n, const ScanPoints& scan,
                                        MatchScore* out) const {
  constexpr int kCells = (2 * W + 1) * (2 * W + 1);
  // The obstacles (hit means, in window order) of one (end point, probe)
  // cell pair, for the beam at hand.
  struct Obstacles {
    uint64_t hit, probe;  // cell_key() of the end point's and the probe's cells
    int count = 0;
    double mx[kCells], my[kCells];
  };
  Obstacles seen[kMaxSameHeading];
  FieldSum sums[kMaxSameHeading];
  for (size_t k = 0; k < n; ++k) sums[k] = FieldSum(map.resolution(), W);
  const double c = std::cos(poses[0].theta), s = std::sin(poses[0].theta);
  for (size_t i = 0; i < scan.hit.size(); ++i) {
    const Point2D& p = scan.hit[i];
    const Point2D& q = scan.free[i];
    // The rotated beam, as for_each_match_in() sums it: (x + c px) - s py.
    const double cpx = c * p.x, spy = s * p.y, spx = s * p.x, cpy = c * p.y;
    const double cqx = c * q.x, sqy = s * q.y, sqx = s * q.x, cqy = c * q.y;
    size_t known = 0;
    for (size_t k = 0; k < n; ++k) {
      const Pose2D& pose = poses[k];
      const double hx = pose.x + cpx - spy, hy = pose.y + spx + cpy;
      const double fx = pose.x + cqx - sqy, fy = pose.y + sqx + cqy;
      const grid::CellIndex hc = map.cell_of(hx, hy), fc = map.cell_of(fx, fy);
      const uint64_t hit_key = cell_key(hc), probe_key = cell_key(fc);
      const Obstacles* o = nullptr;
      for (size_t j = 0; j < known; ++j)
        if ((seen[j].hit == hit_key) & (seen[j].probe == probe_key)) {  // one branch
          o = &seen[j];
          break;
        }
      if (!o) {
        Obstacles& fresh = seen[known++];
        fresh.hit = hit_key;
        fresh.probe = probe_key;
        fresh.count = 0;
        for_each_obstacle<W>(map, hc, fc, occ_threshold_, [&](double mx, double my) {
          fresh.mx[fresh.count] = mx;
          fresh.my[fresh.count] = my;
          ++fresh.count;
        });
        o = &fresh;
      }
      if (o->count == 0) continue;
      double best = std::numeric_limits<double>::infinity();
      for (int j = 0; j < o->count; ++j)
        best = std::min(best,
                        (hx - o->mx[j]) * (hx - o->mx[j]) + (hy - o->my[j]) * (hy - o->my[j]));
      sums[k].add(best);
    }
  }
  for (size_t k = 0; k < n; ++k) out[k] = sums[k].score(scan.hit.size(), inv_2sigma2_);
}

// The hill climbing halves its steps refinements - 1 times.
double ScanMatcher::finest_step(double first) const {
  return first / std::ldexp(1.0, std::max(0, opt_.refinements - 1));
}

double ScanMatcher::finest_angular_step() const { return finest_step(opt_.angular_step); }

double ScanMatcher::finest_linear_step() const { return finest_step(opt_.linear_step); }

double ScanMatcher::heading_basin(double far, int window, double resolution) {
  return window_reach(window, resolution) / std::max(far, 1e-9);
}

// How far off a start the climb at a window still reaches, in multiples of
// the window's reach: the beams whose obstacles lie within it pull the pose
// on. ScanMatcher.AStartAsFarOffAsALongStepIsReached: from 0.25 m (twice the
// coarse window's 0.125 m) the climb alone reaches 19 of 24 starts, from
// 0.28-0.4 m 36 of 96.
constexpr double kClimbCapture = 2.0;

int ScanMatcher::window_reaching(double distance, double resolution) {
  if (!(distance > 0.5 * resolution)) return 0;
  return static_cast<int>(std::min<double>(kMaxWindow, std::ceil(distance / resolution - 0.5)));
}

bool ScanMatcher::steps_over_heading_basin(double far, double resolution) const {
  return far > 0 &&
         heading_basin(far, opt_.coarse_window, resolution) < 0.5 * finest_angular_step();
}

Pose2D ScanMatcher::sweep_heading(const grid::OccupancyGrid& map, const Pose2D& start,
                                  const ScanPoints& scan, int window, double basin) const {
  Pose2D best = start;
  double best_ll =
      score(map, start, scan, window, -std::numeric_limits<double>::infinity()).log_likelihood;
  const int k_max = static_cast<int>(std::ceil(finest_angular_step() / basin));
  for (int k = 1; k <= k_max; ++k)
    for (int sign : {1, -1}) {
      const Pose2D cand(start.x, start.y, wrap_angle(start.theta + sign * k * basin));
      const double ll = score(map, cand, scan, window, best_ll).log_likelihood;
      if (ll > best_ll) {
        best = cand;
        best_ll = ll;
      }
    }
  return best;
}

Pose2D ScanMatcher::hill_climb(const grid::OccupancyGrid& map, const Pose2D& start,
                               const ScanPoints& scan, int window, double* score_out) const {
  Pose2D best = start;
  double best_ll =
      score(map, best, scan, window, -std::numeric_limits<double>::infinity()).log_likelihood;
  double ls = opt_.linear_step, as = opt_.angular_step;
  int refinement = 0;
  // Each move strictly raises the score; the cap guards against long walks
  // along a plateau.
  int moves = 0;
  // The candidate opposite the last move (k ^ 1) is the pose just left,
  // whose score is below the current best: it cannot win, so it is not
  // scored again.
  int came_from = -1;
  while (refinement < opt_.refinements && moves < 100) {
    const Pose2D cand[6] = {
        {best.x + ls, best.y, best.theta}, {best.x - ls, best.y, best.theta},
        {best.x, best.y + ls, best.theta}, {best.x, best.y - ls, best.theta},
        {best.x, best.y, wrap_angle(best.theta + as)},
        {best.x, best.y, wrap_angle(best.theta - as)}};
    int arg = -1;
    double arg_ll = best_ll;
    for (int k = 0; k < 6; ++k) {
      if (k == came_from) continue;
      // Scored only as far as it can still beat the best so far.
      const double ll = score(map, cand[k], scan, window, arg_ll).log_likelihood;
      if (ll > arg_ll) {
        arg = k;
        arg_ll = ll;
      }
    }
    if (arg < 0) {
      ls *= 0.5;
      as *= 0.5;
      ++refinement;
      came_from = -1;
    } else {
      best = cand[arg];
      best_ll = arg_ll;
      came_from = arg ^ 1;
      ++moves;
    }
  }
  *score_out = best_ll;
  return best;
}

int ScanMatcher::normal_equations(const grid::OccupancyGrid& map,
                                  const ScanPoints& scan, const Pose2D& pose,
                                  Eigen::Matrix3d* H, Eigen::Vector3d* g,
                                  MatchScore* score_out) const {
  // Point-to-point residuals r_i = T(pose) p_i - m_i against each beam's
  // nearest hit mean; J_i = [I | dR/dtheta p_i]. The same pass sums the
  // score at `pose` exactly as score() does (same beams, same order), so
  // Gauss-Newton needs one pass per pose instead of two.
  const double c = std::cos(pose.theta), s = std::sin(pose.theta);
  FieldSum sum(map.resolution(), opt_.window);
  double hxt = 0, hyt = 0, htt = 0, gx = 0, gy = 0, gt = 0;
  for_each_match(map, pose, scan, opt_.window,
                 [&](size_t i, double hx, double hy, double d2, const Point2D& m) {
                   const Point2D& p = scan.hit[i];
                   const double jx = -s * p.x - c * p.y, jy = c * p.x - s * p.y;
                   const double rx = hx - m.x, ry = hy - m.y;
                   hxt += jx;
                   hyt += jy;
                   htt += jx * jx + jy * jy;
                   gx += rx;
                   gy += ry;
                   gt += jx * rx + jy * ry;
                   sum.add(d2);
                   return true;
                 });
  const int n = sum.matched();
  *H << n, 0, hxt, 0, n, hyt, hxt, hyt, htt;
  *g << gx, gy, gt;
  *score_out = sum.score(scan.hit.size(), inv_2sigma2_);
  return n;
}

bool ScanMatcher::gauss_newton_step(const Eigen::Matrix3d& H, const Eigen::Vector3d& g,
                                    int matched, Pose2D* pose) {
  if (matched < 6) return false;
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(H);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive() ||
      ldlt.vectorD().minCoeff() <= 1e-9 * H.trace())
    return false;  // degenerate (e.g. a featureless corridor): keep the pose
  const Eigen::Vector3d d = ldlt.solve(-g);
  *pose = perturbed(*pose, d);
  return true;
}

Pose2D ScanMatcher::optimize(const grid::OccupancyGrid& map, const Pose2D& start,
                             const ScanPoints& scan, MatchScore* best_out,
                             Eigen::Matrix3d* information_out) const {
  return optimize(map, start, MatchScan(scan, opt_), best_out, information_out);
}

Pose2D ScanMatcher::optimize(const grid::OccupancyGrid& map, const Pose2D& start,
                             const MatchScan& ready, MatchScore* best_out,
                             Eigen::Matrix3d* information_out, double start_error) const {
  const ScanPoints& scan = ready.points();
  // Coarse: an evenly spread subset of the beams.
  const ScanPoints& coarse = ready.coarse();
  double best_ll = 0.0;
  Pose2D best = hill_climb(map, start, coarse, opt_.coarse_window, &best_ll);
  // A start farther off than the coarse climb reaches (a long step of the
  // odometry: a log with a scan every 2-3 m) leaves most beams without an
  // obstacle in their window, and the climb without a slope to follow. A
  // climb at the window that reaches that far brings the pose into the
  // coarse window's basin, and a coarse climb from there competes with the
  // one from the start: the higher wins. Not a replacement: the wider
  // window's optimum (farther obstacles pulling each beam) may be another
  // basin. And only beyond what the climb reaches by itself
  // (kClimbCapture): tried from the window's reach on, it moved the maps of
  // logs a metre a scan (docs/measurements.md, "A log with a scan every
  // 2-3 m"), some better, more of them worse.
  Pose2D from = start;
  if (start_error > kClimbCapture * window_reach(opt_.coarse_window, map.resolution())) {
    double wide_ll = 0.0;
    from = hill_climb(map, start, coarse, window_reaching(start_error, map.resolution()),
                      &wide_ll);
    if (from.x != start.x || from.y != start.y || from.theta != start.theta) {
      double from_ll = 0.0;
      const Pose2D reached = hill_climb(map, from, coarse, opt_.coarse_window, &from_ll);
      if (from_ll > best_ll) {
        best = reached;
        best_ll = from_ll;
      }
    }
  }
  // Far returns only (outdoors): the climb's heading moves step over the
  // basin the far points leave, and from a start a few mrad off it trades
  // the heading error for a sideways one fitted to the near points. So the
  // climb also starts from the best heading of a sweep at the basin's width
  // around the start (whose position, the odometry's, is good to
  // centimetres; after a long step, where the wide climb ended), and the
  // higher of the climbs wins. Both, because a start farther off than the
  // sweep reaches (a turn) is the climb's own.
  const double far = ready.far();
  if (steps_over_heading_basin(far, map.resolution())) {
    double swept_ll = 0.0;
    const Pose2D swept = hill_climb(
        map,
        sweep_heading(map, from, coarse, opt_.coarse_window,
                      heading_basin(far, opt_.coarse_window, map.resolution())),
        coarse, opt_.coarse_window, &swept_ll);
    if (swept_ll > best_ll) best = swept;
  }
  // Fine: Gauss-Newton on all beams, kept only while the likelihood rises.
  Eigen::Matrix3d H;
  Eigen::Vector3d g;
  MatchScore best_score;
  int matched = normal_equations(map, scan, best, &H, &g, &best_score);
  for (int it = 0; it < opt_.gauss_newton_iterations; ++it) {
    Pose2D cand = best;
    if (!gauss_newton_step(H, g, matched, &cand)) break;
    Eigen::Matrix3d cand_H;
    Eigen::Vector3d cand_g;
    MatchScore sc;
    const int cand_matched = normal_equations(map, scan, cand, &cand_H, &cand_g, &sc);
    if (sc.log_likelihood <= best_score.log_likelihood) break;
    best = cand;
    best_score = sc;
    H = cand_H;
    g = cand_g;
    matched = cand_matched;
  }
  if (best_out) *best_out = best_score;
  if (information_out) *information_out = H * (2.0 * inv_2sigma2_);
  return best;
}

}  // namespace hmt::metric_slam

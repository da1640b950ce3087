#include "hmt/metric_slam/scan_matcher.h"

#include <cmath>
#include <limits>

namespace hmt::metric_slam {

void MatcherOptions::load(Config& cfg, const std::string& s) {
  max_range = cfg.get_double(s, "max_range", max_range);
  beam_skip = cfg.get_int(s, "beam_skip", beam_skip);
  window = cfg.get_int(s, "window", window);
  sigma = cfg.get_double(s, "sigma", sigma);
  occupied_probability = cfg.get_double(s, "occupied_probability", occupied_probability);
  linear_step = cfg.get_double(s, "linear_step", linear_step);
  angular_step = cfg.get_double(s, "angular_step", angular_step);
  refinements = cfg.get_int(s, "refinements", refinements);
  min_match_ratio = cfg.get_double(s, "min_match_ratio", min_match_ratio);
  require(max_range > 0, s, "max_range", "> 0");
  require(beam_skip >= 0, s, "beam_skip", ">= 0");
  require(window >= 0 && window <= 5, s, "window", "in [0, 5]");
  require(sigma > 0, s, "sigma", "> 0");
  require(occupied_probability > 0.5 && occupied_probability < 1, s,
          "occupied_probability", "in (0.5, 1)");
  require(linear_step > 0, s, "linear_step", "> 0");
  require(angular_step > 0, s, "angular_step", "> 0");
  require(refinements >= 0 && refinements <= 20, s, "refinements", "in [0, 20]");
  require(min_match_ratio >= 0 && min_match_ratio <= 1, s, "min_match_ratio",
          "in [0, 1]");
}

ScanMatcher::ScanMatcher(const MatcherOptions& opt) : opt_(opt) {
  const double p = opt.occupied_probability;
  occ_threshold_ = static_cast<int16_t>(
      std::lround(std::log(p / (1 - p)) * grid::kLogOddsScale));
  inv_2sigma2_ = 1.0 / (2.0 * opt.sigma * opt.sigma);
}

MatchScore ScanMatcher::score(const grid::OccupancyGrid& map, const Pose2D& pose,
                              const ScanPoints& scan) const {
  MatchScore out;
  const double c = std::cos(pose.theta), s = std::sin(pose.theta);
  const int w = opt_.window;
  const double res = map.resolution();
  const double max_d2 = (w + 0.5) * (w + 0.5) * res * res;
  const size_t n = scan.hit.size();
  double ll = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const Point2D& p = scan.hit[i];
    const Point2D& f = scan.free[i];
    const double hx = pose.x + c * p.x - s * p.y, hy = pose.y + s * p.x + c * p.y;
    const double fx = pose.x + c * f.x - s * f.y, fy = pose.y + s * f.x + c * f.y;
    const grid::CellIndex hc = map.cell_of(hx, hy), fc = map.cell_of(fx, fy);
    double best = max_d2;
    bool found = false;
    for (int dy = -w; dy <= w; ++dy)
      for (int dx = -w; dx <= w; ++dx) {
        const grid::CellIndex q{hc.x + dx, hc.y + dy};
        const grid::Cell* cell = map.find(q);
        if (!cell || cell->logodds < occ_threshold_) continue;
        const grid::Cell* fcell = map.find({fc.x + dx, fc.y + dy});
        if (fcell && fcell->logodds >= occ_threshold_) continue;
        const Point2D m = map.hit_mean(q, *cell);
        const double d2 = (hx - m.x) * (hx - m.x) + (hy - m.y) * (hy - m.y);
        if (d2 < best) {
          best = d2;
          found = true;
        }
      }
    out.matched += found;
    ll -= best * inv_2sigma2_;
  }
  out.log_likelihood = ll;
  return out;
}

Pose2D ScanMatcher::optimize(const grid::OccupancyGrid& map, const Pose2D& start,
                             const ScanPoints& scan, MatchScore* best_out) const {
  Pose2D best = start;
  MatchScore best_score = score(map, best, scan);
  double ls = opt_.linear_step, as = opt_.angular_step;
  int refinement = 0;
  // Bounded: each improvement strictly raises the score, and the number of
  // moves per refinement level is capped as a guard against plateaus.
  int moves = 0;
  while (refinement < opt_.refinements && moves < 200) {
    const Pose2D cand[6] = {
        {best.x + ls, best.y, best.theta}, {best.x - ls, best.y, best.theta},
        {best.x, best.y + ls, best.theta}, {best.x, best.y - ls, best.theta},
        {best.x, best.y, wrap_angle(best.theta + as)},
        {best.x, best.y, wrap_angle(best.theta - as)}};
    int arg = -1;
    MatchScore arg_score = best_score;
    for (int k = 0; k < 6; ++k) {
      const MatchScore sc = score(map, cand[k], scan);
      if (sc.log_likelihood > arg_score.log_likelihood) {
        arg = k;
        arg_score = sc;
      }
    }
    if (arg < 0) {
      ls *= 0.5;
      as *= 0.5;
      ++refinement;
    } else {
      best = cand[arg];
      best_score = arg_score;
      ++moves;
    }
  }
  if (best_out) *best_out = best_score;
  return best;
}

}  // namespace hmt::metric_slam

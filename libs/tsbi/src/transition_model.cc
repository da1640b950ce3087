#include "hmt/tsbi/transition_model.h"

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "hmt/area/ncut.h"
#include "hmt/common/log_sum_exp.h"
#include "hmt/area/sso_graph.h"
#include "hmt/topology/shortest_paths.h"

namespace hmt::tsbi {
namespace {

using topology::AreaId;
using topology::PoseGaussian;


// The match starts: the prior mean and the lattice {-k, 0, k}^3 along the
// prior's principal axes (whitened by its Cholesky factor).
std::vector<Pose2D> match_starts(const PoseGaussian& prior, double k) {
  const Eigen::Matrix3d L = prior.cov.llt().matrixL();
  std::vector<Pose2D> starts;
  for (int a = -1; a <= 1; ++a)
    for (int b = -1; b <= 1; ++b)
      for (int c = -1; c <= 1; ++c) {
        if (k == 0 && (a || b || c)) continue;
        const Eigen::Vector3d d = L * Eigen::Vector3d(a * k, b * k, c * k);
        starts.emplace_back(prior.mean.x + d.x(), prior.mean.y + d.y(),
                            wrap_angle(prior.mean.theta + d.z()));
      }
  // The mean first: on ties between modes the one found from it is kept.
  std::stable_partition(starts.begin(), starts.end(), [&](const Pose2D& p) {
    return p.x == prior.mean.x && p.y == prior.mean.y && p.theta == prior.mean.theta;
  });
  return starts;
}

metric_slam::MatcherOptions with_window(metric_slam::MatcherOptions o, int window) {
  o.window = window;
  return o;
}

}  // namespace

TransitionModel::TransitionModel(const TsbiOptions& options,
                                 const metric_slam::MatcherOptions& matcher,
                                 double likelihood_gain, const area::AreaOptions& area)
    : opt_(options),
      matcher_(matcher),
      wide_(with_window(matcher, std::max(matcher.coarse_window, 2))),
      gain_(likelihood_gain),
      area_(area) {}

std::vector<Pose2D> TransitionModel::wide_search(const grid::OccupancyGrid& map,
                                                 const PoseGaussian& prior,
                                                 const metric_slam::ScanPoints& obs) const {
  // The lattice spans the gate's bounding box around the prior mean.
  const Eigen::Vector3d half(std::sqrt(opt_.gate * prior.cov(0, 0)),
                             std::sqrt(opt_.gate * prior.cov(1, 1)),
                             std::min(M_PI, std::sqrt(opt_.gate * prior.cov(2, 2))));
  double sx = opt_.search_step_xy, st = opt_.search_step_theta;
  auto count = [&] {
    return (2 * std::floor(half.x() / sx) + 1) * (2 * std::floor(half.y() / sx) + 1) *
           (2 * std::floor(half.z() / st) + 1);
  };
  if (count() > opt_.search_max_poses) {
    const double f = std::cbrt(count() / opt_.search_max_poses);
    sx *= f;
    st *= f;
  }
  const int nx = static_cast<int>(half.x() / sx), ny = static_cast<int>(half.y() / sx),
            nt = static_cast<int>(half.z() / st);
  const metric_slam::ScanPoints sub = metric_slam::spread_subset(obs, opt_.search_points);
  const Eigen::Matrix3d S_inv = prior.cov.inverse();
  struct Cand {
    double ll;
    Pose2D pose;
  };
  std::vector<Cand> cands;
  for (int t = -nt; t <= nt; ++t)
    for (int y = -ny; y <= ny; ++y)
      for (int x = -nx; x <= nx; ++x) {
        const Eigen::Vector3d e(x * sx, y * sx, t * st);
        if (e.dot(S_inv * e) > opt_.gate) continue;
        const Pose2D p(prior.mean.x + e.x(), prior.mean.y + e.y(),
                       wrap_angle(prior.mean.theta + e.z()));
        cands.push_back({wide_.score(map, p, sub).log_likelihood, p});
      }
  // Best first (ties in lattice order), then keep maxima at least two
  // lattice steps apart.
  std::stable_sort(cands.begin(), cands.end(),
                   [](const Cand& a, const Cand& b) { return a.ll > b.ll; });
  std::vector<Pose2D> out;
  for (const Cand& c : cands) {
    if (static_cast<int>(out.size()) >= opt_.search_modes) break;
    const bool near = std::any_of(out.begin(), out.end(), [&](const Pose2D& q) {
      return std::fabs(c.pose.x - q.x) < 2 * sx && std::fabs(c.pose.y - q.y) < 2 * sx &&
             std::fabs(wrap_angle(c.pose.theta - q.theta)) < 2 * st;
    });
    if (!near) out.push_back(c.pose);
  }
  return out;
}

bool TransitionModel::same_area(const topology::Area& area, const Pose2D& robot,
                                const Observations& obs) const {
  if (area.keyframes.empty() || obs.scans.empty()) return true;  // nothing to check with
  // The area's keyframes nearest to the robot, then the latest scans placed
  // at the mode; ids: area keyframes first.
  std::vector<size_t> order(area.keyframes.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  auto dist = [&](size_t i) {
    const Pose2D d = area.keyframes[i].pose - robot;
    return d.x * d.x + d.y * d.y;
  };
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return dist(a) < dist(b); });
  if (order.size() > static_cast<size_t>(opt_.area_check_keyframes))
    order.resize(static_cast<size_t>(opt_.area_check_keyframes));
  std::sort(order.begin(), order.end());
  area::SsoGraph graph(area_);
  int id = 0;
  for (size_t i : order)
    graph.add(id++, {area::PoseGaussian(area.keyframes[i].pose), area.keyframes[i].scan});
  std::vector<char> in_latest(order.size(), 0);
  for (const PosedScan& ps : obs.scans) {
    graph.add(id++, {area::PoseGaussian(robot + ps.pose), *ps.scan});
    in_latest.push_back(1);
  }
  const area::WeightMatrix W = graph.weight_matrix(graph.ids());
  return area::normalized_cut(W, in_latest) >= area_.partition.tau;
}

ExpectedLikelihood TransitionModel::expected_likelihood(
    const grid::OccupancyGrid& map, const PoseGaussian& prior_in,
    const Observations& observations) const {
  ExpectedLikelihood out;
  const metric_slam::ScanPoints& obs = observations.points;
  // Log-likelihoods of the kept points stand for all the points.
  const double k = observations.scale / gain_;
  const size_t n = obs.hit.size();
  if (n == 0) return out;
  PoseGaussian prior = prior_in;
  prior.cov.diagonal() += Eigen::Vector3d(opt_.prior_std_xy * opt_.prior_std_xy,
                                          opt_.prior_std_xy * opt_.prior_std_xy,
                                          opt_.prior_std_theta * opt_.prior_std_theta);
  const Eigen::Matrix3d S = prior.cov;
  const Eigen::Matrix3d S_inv = S.inverse();
  // l0: every point at the truncation distance (an empty map explains none).
  const grid::OccupancyGrid empty(map.resolution());
  const double l0 = matcher_.score(empty, Pose2D(), obs).log_likelihood * k;

  struct Mode {
    Pose2D pose;
    double log_contribution;
    double ratio;
    Eigen::Matrix3d H;
  };
  std::vector<Mode> modes;
  std::vector<Pose2D> starts = match_starts(prior, opt_.start_sigmas);
  // A prior much wider than the matcher's basin (a long loop) is searched
  // on a lattice first.
  if (std::max(prior.cov(0, 0), prior.cov(1, 1)) > 0.3 * 0.3 || prior.cov(2, 2) > 0.1 * 0.1) {
    const std::vector<Pose2D> wide = wide_search(map, prior, obs);
    starts.insert(starts.begin() + 1, wide.begin(), wide.end());
  }
  for (const Pose2D& start : starts) {
    metric_slam::MatchScore ms;
    const Pose2D x = matcher_.optimize(map, start, obs, &ms);
    const double ratio = static_cast<double>(ms.matched) / static_cast<double>(n);
    if (ratio < opt_.min_match_ratio) continue;
    const Eigen::Vector3d e = topology::difference(x, prior.mean);
    if (e.dot(S_inv * e) > opt_.gate) continue;
    const bool seen = std::any_of(modes.begin(), modes.end(), [&](const Mode& m) {
      const Pose2D d = x - m.pose;
      return d.norm() < opt_.mode_merge_distance &&
             std::fabs(d.theta) < opt_.mode_merge_angle;
    });
    if (seen) continue;
    // Laplace around the mode; H is the tempered Gauss-Newton information.
    const Eigen::Matrix3d H = matcher_.information(map, x, obs) * k;
    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
    const double log_det = std::log((I + H * S).determinant());
    const double quad = e.dot(H * (I + S * H).inverse() * e);
    const double l = ms.log_likelihood * k;
    modes.push_back({x, (l - l0) - 0.5 * log_det - 0.5 * quad, ratio, H});
  }
  if (modes.empty()) return out;
  std::vector<double> contributions;
  size_t best = 0;
  for (size_t i = 0; i < modes.size(); ++i) {
    contributions.push_back(modes[i].log_contribution);
    if (modes[i].log_contribution > modes[best].log_contribution) best = i;
  }
  out.candidate = true;
  out.log_f = log_sum_exp(contributions);
  out.modes = static_cast<int>(modes.size());
  out.match_ratio = modes[best].ratio;
  // The pose posterior at the best mode: likelihood (H) times prior (S^-1).
  out.robot.mean = modes[best].pose;
  out.robot.cov = (modes[best].H + S_inv).inverse();
  out.robot.cov = 0.5 * (out.robot.cov + out.robot.cov.transpose());
  return out;
}

std::vector<Outcome> TransitionModel::evaluate(const topology::HmtMap& map,
                                               AreaId current,
                                               const PoseGaussian& robot,
                                               const Observations& obs) const {
  std::vector<Outcome> outcomes(1);
  outcomes[0].log_f = opt_.log_eta;
  // Where every other area's frame lies, seen from the current area.
  const topology::PathTree tree = topology::shortest_paths(map, current);
  // How far the observations reach from the robot.
  double reach_ = 0.0;
  for (const Point2D& p : obs.points.hit) reach_ = std::max(reach_, std::hypot(p.x, p.y));
  for (AreaId id : map.area_ids()) {
    if (id == current || !tree.reaches(id)) continue;
    const auto& area_map = map.area(id).map;
    if (!area_map) continue;
    Outcome o;
    o.area = id;
    // The robot in gamma's frame: (-)Delta_{c,gamma} (+) robot.
    o.prior = topology::relative(robot, tree.pose_of(id));
    // Cheap reach test first: can observations from anywhere in the prior's
    // gate land on the area's map at all?
    grid::CellIndex lo, hi;
    if (!area_map->bounds(&lo, &hi)) continue;
    const double res = area_map->resolution();
    const double reach = reach_ + std::sqrt(opt_.gate * std::max(o.prior.cov(0, 0) +
                                                                 opt_.prior_std_xy * opt_.prior_std_xy,
                                                                 o.prior.cov(1, 1) +
                                                                 opt_.prior_std_xy * opt_.prior_std_xy));
    const double dx = std::max({lo.x * res - o.prior.mean.x, 0.0, o.prior.mean.x - (hi.x + 1) * res});
    const double dy = std::max({lo.y * res - o.prior.mean.y, 0.0, o.prior.mean.y - (hi.y + 1) * res});
    if (std::hypot(dx, dy) > reach) continue;
    const ExpectedLikelihood f = expected_likelihood(*area_map, o.prior, obs);
    if (!f.candidate) continue;
    if (opt_.area_check && !same_area(map.area(id), f.robot.mean, obs)) continue;
    o.log_f = f.log_f;
    o.robot = f.robot;
    o.match_ratio = f.match_ratio;
    o.modes = f.modes;
    outcomes.push_back(o);
  }
  std::vector<double> lf;
  for (const Outcome& o : outcomes) lf.push_back(o.log_f);
  const double z = log_sum_exp(lf);
  for (Outcome& o : outcomes) o.probability = std::exp(o.log_f - z);
  return outcomes;
}

std::vector<size_t> probable_outcomes(const std::vector<Outcome>& outcomes,
                                      double min_probability) {
  std::vector<size_t> kept;
  size_t best = 0;
  for (size_t i = 0; i < outcomes.size(); ++i) {
    if (outcomes[i].probability >= min_probability) kept.push_back(i);
    if (outcomes[i].probability > outcomes[best].probability) best = i;
  }
  if (kept.empty() && !outcomes.empty()) kept.push_back(best);
  return kept;
}

}  // namespace hmt::tsbi

#include "hmt/tsbi/transition_model.h"

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>

#include "hmt/area/cut_off.h"
#include "hmt/tsbi/bnb_matcher.h"
#include "hmt/common/log_sum_exp.h"
#include "hmt/topology/shortest_paths.h"

namespace hmt::tsbi {
namespace {

// The share of the `n` points a match explained.
double share_explained(const metric_slam::MatchScore& s, size_t n) {
  return static_cast<double>(s.matched) / static_cast<double>(n);
}

// How many of the points (robot frame), placed at `pose`, fall within the
// bounds of the cells `map` observed.
size_t points_in_extent(const grid::OccupancyGrid& map, const Pose2D& pose,
                        const std::vector<Point2D>& points) {
  grid::CellIndex lo, hi;
  if (!map.bounds(&lo, &hi)) return 0;
  const double c = std::cos(pose.theta), s = std::sin(pose.theta);
  size_t n = 0;
  for (const Point2D& p : points) {
    const grid::CellIndex q =
        map.cell_of(pose.x + c * p.x - s * p.y, pose.y + s * p.x + c * p.y);
    n += q.x >= lo.x && q.x <= hi.x && q.y >= lo.y && q.y <= hi.y;
  }
  return n;
}

// The points (robot frame), placed at `pose`, that fall where `map` saw clear
// free space: their cell and every cell within `window` of it observed, and
// at most `free_logodds`. Returned in the map's frame.
std::vector<Point2D> points_in_free_space(const grid::OccupancyGrid& map, const Pose2D& pose,
                                          const std::vector<Point2D>& points, int window,
                                          grid::LogOdds free_logodds) {
  const double c = std::cos(pose.theta), s = std::sin(pose.theta);
  std::vector<Point2D> out;
  for (const Point2D& p : points) {
    const Point2D w{pose.x + c * p.x - s * p.y, pose.y + s * p.x + c * p.y};
    const grid::CellIndex q = map.cell_of(w.x, w.y);
    bool clear = true;
    for (int dy = -window; dy <= window && clear; ++dy)
      for (int dx = -window; dx <= window && clear; ++dx) {
        const grid::Cell cell = map.cell({q.x + dx, q.y + dy});
        clear = (cell.logodds != 0 || cell.hits != 0) && cell.logodds <= free_logodds;
      }
    if (clear) out.push_back(w);
  }
  return out;
}

// A surface seen where a map saw through: its points grouped in cells of
// 0.25 m (two returns of a 180-beam laser 14 m away still touch), and the
// group spanning 1 m. A person standing (0.3-0.6 m) or a chair is shorter;
// a wall, a partition or a shelf is not.
constexpr double kSurfaceCell = 0.25;
constexpr double kSurfaceSpan = 1.0;

// How many of `points` belong to groups (points in 8-connected cells of
// `cell` m) whose bounding box spans at least `span` m: a surface, not a
// person standing or a chair moved.
size_t points_in_surfaces(const std::vector<Point2D>& points, double cell, double span) {
  std::map<std::pair<int64_t, int64_t>, int> group_of_cell;  // ordered: deterministic
  std::vector<int> parent, group(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const std::pair<int64_t, int64_t> key{static_cast<int64_t>(std::floor(points[i].x / cell)),
                                          static_cast<int64_t>(std::floor(points[i].y / cell))};
    const auto [it, added] = group_of_cell.try_emplace(key, static_cast<int>(parent.size()));
    if (added) parent.push_back(it->second);
    group[i] = it->second;
  }
  auto root = [&](int a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  for (const auto& [key, g] : group_of_cell)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const auto it = group_of_cell.find({key.first + dx, key.second + dy});
        if (it != group_of_cell.end()) parent[root(g)] = root(it->second);
      }
  struct Box {
    double x0, y0, x1, y1;
    size_t n = 0;
  };
  std::map<int, Box> boxes;
  for (size_t i = 0; i < points.size(); ++i) {
    const Point2D& p = points[i];
    Box& b = boxes.try_emplace(root(group[i]), Box{p.x, p.y, p.x, p.y}).first->second;
    b.x0 = std::min(b.x0, p.x);
    b.y0 = std::min(b.y0, p.y);
    b.x1 = std::max(b.x1, p.x);
    b.y1 = std::max(b.y1, p.y);
    ++b.n;
  }
  size_t n = 0;
  for (const auto& [r, b] : boxes)
    if (std::hypot(b.x1 - b.x0, b.y1 - b.y0) >= span) n += b.n;
  return n;
}

using topology::AreaId;
using topology::PoseGaussian;

// The variances the prior's floors add (TsbiOptions::prior_std_*).
Eigen::Vector3d prior_floor(const TsbiOptions& o) {
  return Eigen::Vector3d(o.prior_std_xy * o.prior_std_xy, o.prior_std_xy * o.prior_std_xy,
                         o.prior_std_theta * o.prior_std_theta);
}

// A report of `area` under `prior`, its verdict still to be given.
CandidateReport candidate_report(AreaId area, const PoseGaussian& prior) {
  CandidateReport r;
  r.area = area;
  r.prior_mean = prior.mean;
  r.prior_sd = prior.cov.diagonal().cwiseMax(0.0).cwiseSqrt();
  return r;
}

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
        starts.push_back(perturbed(prior.mean, d));
      }
  // The mean first: on ties between modes the one found from it is kept.
  std::stable_partition(starts.begin(), starts.end(), [&](const Pose2D& p) {
    return p.x == prior.mean.x && p.y == prior.mean.y && p.theta == prior.mean.theta;
  });
  return starts;
}

// An upper bound on the bytes of a map's match field (one per cell over its
// obstacles' bounding box): the cells of its tiles' bounding box.
size_t field_bytes_bound(const grid::OccupancyGrid& map) {
  grid::CellIndex lo, hi;
  if (!map.bounds(&lo, &hi)) return 0;
  return static_cast<size_t>(hi.x - lo.x + 1) * static_cast<size_t>(hi.y - lo.y + 1);
}

}  // namespace

TransitionModel::TransitionModel(const TsbiOptions& options,
                                 const metric_slam::MatcherOptions& matcher,
                                 double likelihood_gain, const area::AreaOptions& area,
                                 std::shared_ptr<WorkerPool> pool)
    : opt_(options),
      matcher_(matcher),
      free_threshold_(grid::scaled_logit(options.free_probability)),
      gain_(likelihood_gain),
      area_(area),
      pool_(std::move(pool)) {}

void TransitionModel::for_each_index(size_t n, const std::function<void(size_t)>& fn) const {
  if (pool_) {
    pool_->parallel_for(n, fn);
  } else {
    for (size_t i = 0; i < n; ++i) fn(i);
  }
}

namespace {

// The wide search's lattice over the gate's bounding box: steps (m, rad),
// the translation step in whole cells, and the half-extent in steps.
struct Lattice {
  double sx = 0.0, st = 0.0;
  int step_cells = 1;
  int nx = 0, ny = 0, nt = 0;
};

Lattice gate_lattice(const PoseGaussian& prior, const TsbiOptions& opt, double res) {
  const Eigen::Vector3d half(std::sqrt(opt.gate * prior.cov(0, 0)),
                             std::sqrt(opt.gate * prior.cov(1, 1)),
                             std::min(M_PI, std::sqrt(opt.gate * prior.cov(2, 2))));
  Lattice l;
  l.sx = opt.search_step_xy;
  l.st = opt.search_step_theta;
  auto count = [&] {
    return (2 * std::floor(half.x() / l.sx) + 1) * (2 * std::floor(half.y() / l.sx) + 1) *
           (2 * std::floor(half.z() / l.st) + 1);
  };
  if (count() > opt.search_max_poses) {
    const double f = std::cbrt(count() / opt.search_max_poses);
    l.sx *= f;
    l.st *= f;
  }
  // Translation steps of whole cells: a point's cell then moves by whole
  // cells across the (x, y) lattice, so each angle needs one rotation.
  l.step_cells = std::max(1, static_cast<int>(std::lround(l.sx / res)));
  l.sx = l.step_cells * res;
  l.nx = static_cast<int>(half.x() / l.sx);
  l.ny = static_cast<int>(half.y() / l.sx);
  l.nt = static_cast<int>(half.z() / l.st);
  return l;
}

struct Scored {
  double score;
  Pose2D pose;
};

// Best first (ties in lattice order), keeping poses at least two lattice
// steps from every pose kept before; at most `count`.
std::vector<Pose2D> separated_maxima(std::vector<Scored> cands, const Lattice& l, int count) {
  std::stable_sort(cands.begin(), cands.end(),
                   [](const Scored& a, const Scored& b) { return a.score > b.score; });
  std::vector<Pose2D> out;
  for (const Scored& c : cands) {
    if (static_cast<int>(out.size()) >= count) break;
    const bool near = std::any_of(out.begin(), out.end(), [&](const Pose2D& q) {
      return std::fabs(c.pose.x - q.x) < 2 * l.sx && std::fabs(c.pose.y - q.y) < 2 * l.sx &&
             std::fabs(wrap_angle(c.pose.theta - q.theta)) < 2 * l.st;
    });
    if (!near) out.push_back(c.pose);
  }
  return out;
}

}  // namespace

std::vector<Pose2D> TransitionModel::wide_search(const MatchField& field,
                                                 const PoseGaussian& prior,
                                                 const metric_slam::ScanPoints& obs) const {
  const double res = field.resolution();
  const Lattice l = gate_lattice(prior, opt_, res);
  const std::vector<Point2D> pts = metric_slam::spread_subset(obs, opt_.search_points).hit;
  // A point's cost: its squared distance (cells) to the nearest obstacle,
  // truncated half a cell beyond the wide window, as the matcher's
  // likelihood field is truncated at its window.
  const double reach = std::max(matcher_.options().coarse_window, 2) + 0.5;
  double cost[MatchField::kFar + 1];
  for (int d = 0; d <= MatchField::kFar; ++d) cost[d] = std::min(d * d * 1.0, reach * reach);
  const Eigen::Matrix3d S_inv = prior.cov.inverse();
  std::vector<Scored> cands;
  std::vector<int> bx(pts.size()), by(pts.size());
  for (int t = -l.nt; t <= l.nt; ++t) {
    // The points' cells at this angle with the lattice's central translation.
    const double th = prior.mean.theta + t * l.st;
    const double c = std::cos(th), s = std::sin(th);
    for (size_t i = 0; i < pts.size(); ++i) {
      bx[i] = MatchField::floor_cell((prior.mean.x + c * pts[i].x - s * pts[i].y) / res);
      by[i] = MatchField::floor_cell((prior.mean.y + s * pts[i].x + c * pts[i].y) / res);
    }
    for (int y = -l.ny; y <= l.ny; ++y)
      for (int x = -l.nx; x <= l.nx; ++x) {
        const Eigen::Vector3d e(x * l.sx, y * l.sx, t * l.st);
        if (e.dot(S_inv * e) > opt_.gate) continue;
        double score = 0.0;
        for (size_t i = 0; i < pts.size(); ++i)
          score -= cost[field.distance(bx[i] + x * l.step_cells, by[i] + y * l.step_cells)];
        cands.push_back({score, Pose2D(prior.mean.x + e.x(), prior.mean.y + e.y(),
                                       wrap_angle(th))});
      }
  }
  return separated_maxima(std::move(cands), l, opt_.search_modes);
}

std::vector<Pose2D> TransitionModel::bnb_search(const CostStack& stack, const MatchField& field,
                                                const PoseGaussian& prior,
                                                const metric_slam::ScanPoints& obs) const {
  const std::vector<Point2D> pts = metric_slam::spread_subset(obs, opt_.search_points).hit;
  // The roots may take a quarter of the budget, the rest going to the
  // descent from them.
  const SearchLattice l = budget_lattice(
      stack, gate_lattice(prior, opt_.gate, opt_.bnb_step_xy, opt_.bnb_step_theta, field.resolution()),
      pts, opt_.bnb_max_blocks / 4);
  ModeQuery q;
  q.count = opt_.search_modes;
  q.separation_xy = opt_.bnb_separation_xy;
  q.separation_theta = opt_.bnb_separation_theta;
  q.max_blocks = opt_.bnb_max_blocks;
  q.margin = static_cast<int64_t>(
      std::floor(opt_.bnb_margin * static_cast<double>(pts.size()) * stack.max_cost()));
  // No start is wanted where no mode can pass the ratio gate: a lattice
  // pose is a start only if its cost is at most that of min_points_explained
  // of the points `window` cells from an obstacle (matched, as the ratio
  // gate counts them) and the rest saturated. (A limit on the search's
  // effort in the ratio gate's terms, not a proof: the refined mode lies up
  // to half a lattice step away, and the search's points are a subset.)
  const double rho = opt_.min_points_explained;
  const int near_cost = CostStack::point_cost(matcher_.options().window,
                                              matcher_.options().coarse_window);
  q.max_cost = static_cast<int64_t>(std::floor(
      static_cast<double>(pts.size()) * (rho * near_cost + (1.0 - rho) * stack.max_cost())));
  std::vector<Pose2D> out;
  for (const SearchMode& m : bnb_modes(stack, l, pts, q)) out.push_back(m.pose);
  return out;
}

bool TransitionModel::same_area(const topology::Area& area, const Pose2D& robot,
                                const Observations& obs) const {
  if (area.keyframes.empty() || obs.scans.empty()) return true;  // nothing to check with
  // The area's keyframes nearest to the robot, against the latest scans
  // placed at the mode.
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
  std::vector<area::Keyframe> keyframes;
  for (size_t i : order)
    keyframes.push_back({area::PoseGaussian(area.keyframes[i].pose), area.keyframes[i].scan});
  std::vector<area::Keyframe> latest;
  for (const PosedScan& ps : obs.scans)
    latest.push_back({area::PoseGaussian(robot + ps.pose), *ps.scan});
  return !area::cut_off(keyframes, latest, area_, area_.partition.tau, area_check_pairs_);
}

ExpectedLikelihood TransitionModel::expected_likelihood(
    const grid::OccupancyGrid& map, const PoseGaussian& prior,
    const Observations& observations) const {
  return expected_likelihood(map, MatchField(map, matcher_.occupied_threshold()), prior,
                             observations);
}

TransitionModel::Search TransitionModel::prepare_search(const grid::OccupancyGrid& map,
                                                        const MatchField& field,
                                                        const PoseGaussian& prior_in,
                                                        const Observations& observations) const {
  Search out;
  const metric_slam::ScanPoints& obs = observations.points;
  if (obs.hit.empty()) return out;
  // Log-likelihoods of the kept points stand for all the points, as the
  // observations were gathered: for the distinct cells they hit, tempered
  // by evidence_gain (one patch of surface is one piece of evidence however
  // many returns it gave), or for every return, tempered as the metric
  // filter's weights.
  out.scale = observations.evidence_cell > 0
                  ? static_cast<double>(observations.surface_cells) / opt_.evidence_gain /
                        static_cast<double>(obs.hit.size())
                  : observations.scale / gain_;
  out.prior = prior_in;
  out.prior.cov.diagonal() += prior_floor(opt_);
  const PoseGaussian& prior = out.prior;
  // No mode can pass the ratio gate if no pose in the prior's gate lets
  // enough points reach an obstacle: not a candidate, as the matching
  // would conclude, at a fraction of its cost.
  if (opt_.bound_boxes > 0 &&
      !may_reach_ratio(field, obs.hit, prior, opt_.gate, opt_.min_points_explained,
                       matcher_.options().window, opt_.bound_boxes))
    return out;
  out.prior_inverse = prior.cov.inverse();
  // l0: every point at the truncation distance (an empty map explains none).
  const grid::OccupancyGrid empty(map.resolution());
  out.l0 = matcher_.score(empty, Pose2D(), obs).log_likelihood * out.scale;
  out.starts = match_starts(prior, opt_.start_sigmas);
  // A prior much wider than the matcher's basin (a long loop) is searched
  // as a whole first (add_wide_starts).
  out.wide = std::max(prior.cov(0, 0), prior.cov(1, 1)) > 0.3 * 0.3 || prior.cov(2, 2) > 0.1 * 0.1;
  return out;
}

void TransitionModel::add_wide_starts(Search* search, const MatchField& field,
                                      const CostStack* stack, const Observations& obs) const {
  if (!search->wide) return;
  const std::vector<Pose2D> wide = opt_.search == TsbiOptions::WideSearch::kBnb
                                       ? bnb_search(*stack, field, search->prior, obs.points)
                                       : wide_search(field, search->prior, obs.points);
  search->starts.insert(search->starts.begin() + 1, wide.begin(), wide.end());
}

std::shared_ptr<const CostStack> TransitionModel::make_stack(const MatchField& field) const {
  const int step = std::max(1, static_cast<int>(std::lround(opt_.bnb_step_xy / field.resolution())));
  return std::make_shared<const CostStack>(field, matcher_.options().coarse_window, step,
                                           opt_.bnb_levels);
}

TransitionModel::Match TransitionModel::match_from(const grid::OccupancyGrid& map,
                                                   const Pose2D& start, const Observations& obs,
                                                   const metric_slam::MatchScan& ready) const {
  Match m;
  m.pose = matcher_.optimize(map, start, ready, &m.score, &m.information);
  // Only a match that explains min_points_explained of the points reaches
  // the ratio gate's count within the extent (sum_modes).
  if (share_explained(m.score, obs.points.hit.size()) >= opt_.min_points_explained) {
    m.in_extent = points_in_extent(map, m.pose, obs.points.hit);
    // The surfaces in free space, only for a match that passes the ratio
    // gate too (sum_modes drops the others first): it costs a walk over the
    // points' windows.
    if (opt_.max_points_contradicted < 1.0 && explains_extent(m))
      m.contradicted = points_in_surfaces(
          points_in_free_space(map, m.pose, obs.points.hit, matcher_.options().window,
                               free_threshold_),
          kSurfaceCell, kSurfaceSpan);
  }
  return m;
}

bool TransitionModel::explains_extent(const Match& m) const {
  const double within = std::max<double>(static_cast<double>(m.in_extent), m.score.matched);
  return static_cast<double>(m.score.matched) >= opt_.min_match_ratio * within;
}

ExpectedLikelihood TransitionModel::sum_modes(const Search& search,
                                              const std::vector<Match>& matches,
                                              const Observations& observations) const {
  ExpectedLikelihood out;
  const size_t n = observations.points.hit.size();
  const PoseGaussian& prior = search.prior;
  const Eigen::Matrix3d& S = prior.cov;
  const Eigen::Matrix3d& S_inv = search.prior_inverse;
  const double k = search.scale;
  struct Mode {
    Pose2D pose;
    double log_contribution;
    double ratio;
    Eigen::Matrix3d H;
  };
  std::vector<Mode> modes;
  for (const Match& m : matches) {
    const Pose2D& x = m.pose;
    const double ratio = share_explained(m.score, n);
    if (ratio < opt_.min_points_explained) continue;
    if (!explains_extent(m)) continue;
    if (static_cast<double>(m.contradicted) > opt_.max_points_contradicted * static_cast<double>(n))
      continue;
    const Eigen::Vector3d e = topology::difference(x, prior.mean);
    if (e.dot(S_inv * e) > opt_.gate) continue;
    const bool seen = std::any_of(modes.begin(), modes.end(), [&](const Mode& md) {
      return within_spacing(x - md.pose, opt_.mode_merge_distance, opt_.mode_merge_angle);
    });
    if (seen) continue;
    // Laplace around the mode; H is the tempered Gauss-Newton information.
    const Eigen::Matrix3d H = m.information * k;
    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
    const double log_det = std::log((I + H * S).determinant());
    const double quad = e.dot(H * (I + S * H).inverse() * e);
    const double l = m.score.log_likelihood * k;
    modes.push_back({x, (l - search.l0) - 0.5 * log_det - 0.5 * quad, ratio, H});
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

ExpectedLikelihood TransitionModel::expected_likelihood(
    const grid::OccupancyGrid& map, const MatchField& field, const PoseGaussian& prior,
    const Observations& obs) const {
  Search search = prepare_search(map, field, prior, obs);
  std::shared_ptr<const CostStack> stack;
  if (search.wide && opt_.search == TsbiOptions::WideSearch::kBnb) stack = make_stack(field);
  add_wide_starts(&search, field, stack.get(), obs);
  std::vector<Match> matches;
  const metric_slam::MatchScan ready(obs.points, matcher_.options());
  for (const Pose2D& start : search.starts) matches.push_back(match_from(map, start, obs, ready));
  return sum_modes(search, matches, obs);
}

std::vector<Outcome> TransitionModel::reachable_areas(
    const topology::HmtMap& map, AreaId current, const PoseGaussian& robot,
    const Observations& obs, std::vector<CandidateReport>* out_of_reach) const {
  std::vector<Outcome> out;
  // Where every other area's frame lies, seen from the current area.
  const topology::PathTree tree = topology::shortest_paths(map, current);
  // How far the observations reach from the robot.
  double reach_ = 0.0;
  for (const Point2D& p : obs.points.hit) reach_ = std::max(reach_, std::hypot(p.x, p.y));
  const Eigen::Vector3d floor = prior_floor(opt_);
  for (AreaId id : map.area_ids()) {
    if (id == current || !tree.reaches(id)) continue;
    const auto& area_map = map.area(id).map;
    if (!area_map) continue;
    Outcome o;
    o.area = id;
    // The robot in gamma's frame: (-)Delta_{c,gamma} (+) robot.
    o.prior = topology::relative(robot, candidate_frame(map, tree, current, id, opt_));
    // Cheap reach test first: can observations from anywhere in the prior's
    // gate land on the area's map at all?
    // (An empty map is beyond any reach.)
    grid::CellIndex lo, hi;
    bool within = area_map->bounds(&lo, &hi);
    if (within) {
      const double res = area_map->resolution();
      const double reach = reach_ + std::sqrt(opt_.gate * std::max(o.prior.cov(0, 0) + floor(0),
                                                                   o.prior.cov(1, 1) + floor(1)));
      const double dx =
          std::max({lo.x * res - o.prior.mean.x, 0.0, o.prior.mean.x - (hi.x + 1) * res});
      const double dy =
          std::max({lo.y * res - o.prior.mean.y, 0.0, o.prior.mean.y - (hi.y + 1) * res});
      within = std::hypot(dx, dy) <= reach;
    }
    if (!within) {
      if (out_of_reach) {
        out_of_reach->push_back(candidate_report(id, o.prior));
      }
      continue;
    }
    out.push_back(o);
  }
  return out;
}

namespace {

// Drops the least recently used entries of `cache` (the oldest `used` first,
// then in map address order -- which only decides what is rebuilt later,
// never a result) until `bytes()` is within `budget`; never one `in_use`.
template <class Cache, class Bytes, class InUse>
void evict_least_recent(Cache& cache, size_t budget, Bytes&& bytes, InUse&& in_use) {
  while (bytes() > budget) {
    auto victim = cache.end();
    for (auto it = cache.begin(); it != cache.end(); ++it)
      if (!in_use(it->second) &&
          (victim == cache.end() || it->second.used < victim->second.used))
        victim = it;
    if (victim == cache.end()) break;
    cache.erase(victim);
  }
}

}  // namespace

std::vector<std::shared_ptr<const MatchField>> TransitionModel::fields_for(
    const std::vector<std::shared_ptr<const grid::OccupancyGrid>>& maps) {
  // A map only the cache still holds belongs to no hypothesis any more.
  for (auto it = fields_.begin(); it != fields_.end();)
    it = it->second.map.use_count() == 1 ? fields_.erase(it) : std::next(it);
  ++field_calls_;
  std::vector<std::shared_ptr<const grid::OccupancyGrid>> missing;
  for (const auto& m : maps) {
    const auto it = fields_.find(m.get());
    if (it != fields_.end())
      it->second.used = field_calls_;
    else if (std::find(missing.begin(), missing.end(), m) == missing.end())
      missing.push_back(m);
  }
  std::vector<std::shared_ptr<const MatchField>> built(missing.size());
  for_each_index(missing.size(), [&](size_t i) {
    built[i] = std::make_shared<const MatchField>(*missing[i], matcher_.occupied_threshold());
  });
  for (size_t i = 0; i < missing.size(); ++i)
    fields_[missing[i].get()] = {missing[i], built[i], field_calls_};
  std::vector<std::shared_ptr<const MatchField>> out;
  for (const auto& m : maps) out.push_back(fields_.at(m.get()).field);
  // Over the budget: the least recently used go, never one this call uses.
  // A field is a function of its map alone, so what is evicted and rebuilt
  // never changes a result.
  evict_least_recent(fields_, static_cast<size_t>(opt_.field_cache_mb) << 20,
                     [&] { return cached_field_bytes(); },
                     [&](const CachedField& f) { return f.used == field_calls_; });
  return out;
}

std::shared_ptr<const CostStack> TransitionModel::stack_for(
    const grid::OccupancyGrid* map, const std::shared_ptr<const MatchField>& field) {
  {
    std::lock_guard<std::mutex> lock(stacks_mutex_);
    const auto it = stacks_.find(map);
    if (it != stacks_.end() && it->second.field == field) {
      it->second.used = ++stack_calls_;
      return it->second.stack;
    }
    // Back within the budget before building: the stack this thread last
    // searched with may still be cached beyond it.
    trim_stacks();
  }
  // Built outside the lock: the other threads go on searching meanwhile.
  auto stack = make_stack(*field);
  std::lock_guard<std::mutex> lock(stacks_mutex_);
  stacks_[map] = {field, stack, ++stack_calls_};
  trim_stacks();
  return stack;
}

void TransitionModel::trim_stacks() {
  // Stacks of maps whose fields went (no hypothesis holds the map, or the
  // field was rebuilt) go first; then, over the budget, the least recently
  // used, but never one a search holds now (it would only be rebuilt).
  for (auto it = stacks_.begin(); it != stacks_.end();) {
    const auto f = fields_.find(it->first);
    it = f != fields_.end() && f->second.field == it->second.field ? std::next(it)
                                                                    : stacks_.erase(it);
  }
  evict_least_recent(stacks_, static_cast<size_t>(opt_.bnb_cache_mb) << 20,
                     [&] { return cached_stack_bytes(); },
                     [](const CachedStack& s) { return s.stack.use_count() > 1; });
}

size_t TransitionModel::cached_field_bytes() const {
  size_t n = 0;
  for (const auto& [key, f] : fields_) n += f.field->bytes();
  return n;
}

size_t TransitionModel::cached_stack_bytes() const {
  size_t n = 0;
  for (const auto& [key, s] : stacks_) n += s.stack->bytes();
  return n;
}

std::vector<Outcome> TransitionModel::evaluate(const topology::HmtMap& map,
                                               AreaId current,
                                               const PoseGaussian& robot,
                                               const Observations& obs,
                                               std::vector<CandidateReport>* considered) {
  std::vector<std::vector<CandidateReport>> reports;
  std::vector<std::vector<Outcome>> out =
      evaluate_all({Query{&map, current, robot, &obs}}, considered ? &reports : nullptr);
  if (considered) *considered = std::move(reports.front());
  return std::move(out.front());
}

std::vector<std::vector<Outcome>> TransitionModel::evaluate_all(
    const std::vector<Query>& queries, std::vector<std::vector<CandidateReport>>* considered) {
  // The known areas of every query, as tasks in (query, area id) order.
  struct Task {
    size_t query = 0;
    Outcome outcome;  // the area's id and prior; F and the pose once weighed
    const topology::Area* area = nullptr;  // in the query's map
  };
  std::vector<Task> tasks;
  std::vector<std::vector<CandidateReport>> out_of_reach(queries.size());
  for (size_t q = 0; q < queries.size(); ++q) {
    const Query& query = queries[q];
    for (Outcome& o : reachable_areas(*query.map, query.current, query.robot,
                                      *query.observations,
                                      considered ? &out_of_reach[q] : nullptr)) {
      const topology::Area* area = &query.map->area(o.area);
      tasks.push_back({q, std::move(o), area});
    }
  }
  const auto obs_of = [&](const Task& t) -> const Observations& {
    return *queries[t.query].observations;
  };
  // Each area and each of its starts is computed on its own, and the modes
  // are summed in start order: the order of the threads cannot matter.
  //
  // The searches are set up a group of areas at a time: an area's match
  // field (for the bound and the wide search) lives only while its group
  // is set up, and its cost stack (the wide search's) only while its
  // search runs, unless the caches keep them. So an event with many
  // candidates holds at most the caches' budgets, a group's fields and a
  // stack per thread, not every candidate's: outdoors, areas of 100 m and
  // more have fields of 5-10 MB and stacks of 30-50 MB (on the simulated
  // campus the peak went from 372 to 269 MB), while indoors a group is
  // usually the whole event. Each area is one task, its set-up and wide
  // search together, taken by whichever thread is free: the searches'
  // costs differ a hundredfold (a look-alike corridor under a wide prior
  // against a room), and searching them two by two in step left a thread
  // idle for much of the Infinite Corridor's late events.
  std::vector<Search> searches(tasks.size());
  const size_t group = pool_ ? static_cast<size_t>(std::max(pool_->threads(), 1)) : 1;
  // A group: areas in order until their fields would pass the field
  // cache's budget, and at least one area per thread.
  const size_t budget = static_cast<size_t>(opt_.field_cache_mb) << 20;
  for (size_t first = 0, end = 0; first < tasks.size(); first = end) {
    std::vector<std::shared_ptr<const grid::OccupancyGrid>> maps;
    for (size_t bytes = 0; end < tasks.size(); ++end) {
      const size_t b = field_bytes_bound(*tasks[end].area->map);
      if (end - first >= group && bytes + b > budget) break;
      bytes += b;
      maps.push_back(tasks[end].area->map);
    }
    const auto fields = fields_for(maps);
    for_each_index(end - first, [&](size_t j) {
      const Task& t = tasks[first + j];
      Search& search = searches[first + j];
      search = prepare_search(*t.area->map, *fields[j], t.outcome.prior, obs_of(t));
      std::shared_ptr<const CostStack> stack;
      if (search.wide && opt_.search == TsbiOptions::WideSearch::kBnb)
        stack = stack_for(t.area->map.get(), fields[j]);
      add_wide_starts(&search, *fields[j], stack.get(), obs_of(t));
    });
  }
  // Nothing needed any more: the cache drops maps no hypothesis holds and
  // comes back within its budget.
  {
    std::lock_guard<std::mutex> lock(stacks_mutex_);
    trim_stacks();
  }
  std::vector<std::pair<size_t, size_t>> jobs;  // (task, start)
  std::vector<std::vector<Match>> matches(tasks.size());
  for (size_t i = 0; i < tasks.size(); ++i) {
    matches[i].resize(searches[i].starts.size());
    for (size_t k = 0; k < searches[i].starts.size(); ++k) jobs.emplace_back(i, k);
  }
  std::vector<metric_slam::MatchScan> ready;
  ready.reserve(queries.size());
  for (const Query& query : queries) ready.emplace_back(query.observations->points, matcher_.options());
  for_each_index(jobs.size(), [&](size_t j) {
    const auto [i, k] = jobs[j];
    matches[i][k] = match_from(*tasks[i].area->map, searches[i].starts[k], obs_of(tasks[i]),
                               ready[tasks[i].query]);
  });
  std::vector<char> candidate(tasks.size(), 0);
  std::vector<CandidateReport> reports(considered ? tasks.size() : 0);
  for_each_index(tasks.size(), [&](size_t i) {
    Task& t = tasks[i];
    const Observations& obs = obs_of(t);
    const ExpectedLikelihood f = sum_modes(searches[i], matches[i], obs);
    using V = CandidateReport::Verdict;
    auto report = [&](V verdict) {
      if (!considered) return;
      CandidateReport& r = reports[i];
      r = candidate_report(t.outcome.area, t.outcome.prior);
      r.verdict = verdict;
      r.wide = searches[i].wide;
      r.starts = static_cast<uint32_t>(searches[i].starts.size());
      for (const Match& m : matches[i])
        r.best_ratio = std::max(r.best_ratio, share_explained(m.score, obs.points.hit.size()));
      if (f.candidate) r.log_f = f.log_f;
    };
    if (!f.candidate) return report(searches[i].starts.empty() ? V::kBound : V::kNoMode);
    // Less probable than min_probability against the unexplored area
    // alone, it could never get a hypothesis: not an outcome, and not
    // worth the area check (a third of the Infinite Corridor's late
    // events went to checking such look-alikes).
    if (f.log_f < opt_.log_eta + std::log(opt_.min_probability)) return report(V::kImprobable);
    if (opt_.area_check && !same_area(*t.area, f.robot.mean, obs)) return report(V::kAreaCheck);
    report(V::kOutcome);
    Outcome& o = t.outcome;
    o.log_f = f.log_f;
    o.robot = f.robot;
    o.match_ratio = f.match_ratio;
    o.modes = f.modes;
    candidate[i] = 1;
  });
  // Per query: the unexplored area first, then its candidates in id order.
  std::vector<std::vector<Outcome>> out(queries.size(), std::vector<Outcome>(1));
  for (std::vector<Outcome>& outcomes : out) outcomes[0].log_f = opt_.log_eta;
  for (size_t i = 0; i < tasks.size(); ++i)
    if (candidate[i]) out[tasks[i].query].push_back(std::move(tasks[i].outcome));
  for (std::vector<Outcome>& outcomes : out) {
    std::vector<double> lf;
    for (const Outcome& o : outcomes) lf.push_back(o.log_f);
    const std::vector<double> p = normalised_exp(std::move(lf));
    for (size_t i = 0; i < outcomes.size(); ++i) outcomes[i].probability = p[i];
  }
  if (considered) {
    *considered = std::move(out_of_reach);
    for (size_t i = 0; i < tasks.size(); ++i)
      (*considered)[tasks[i].query].push_back(std::move(reports[i]));
    for (std::vector<CandidateReport>& c : *considered)
      std::sort(c.begin(), c.end(),
                [](const CandidateReport& a, const CandidateReport& b) { return a.area < b.area; });
  }
  return out;
}

topology::PoseGaussian candidate_frame(const topology::HmtMap& map,
                                       const topology::PathTree& tree,
                                       topology::AreaId current, topology::AreaId id,
                                       const TsbiOptions& options) {
  topology::PoseGaussian frame = tree.pose_of(id);
  if (tree.nodes.at(id).parent == current || !map.has_arc(current, id)) return frame;
  const topology::PoseGaussian direct = map.arc(current, id);
  const Eigen::Vector3d d = topology::difference(direct.mean, frame.mean);
  Eigen::Matrix3d S = frame.cov + direct.cov;
  S.diagonal() += prior_floor(options);
  if (d.dot(S.ldlt().solve(d)) > options.gate) frame.cov += d * d.transpose();
  return frame;
}

const char* verdict_name(CandidateReport::Verdict v) {
  switch (v) {
    case CandidateReport::Verdict::kOutOfReach: return "out_of_reach";
    case CandidateReport::Verdict::kBound: return "bound";
    case CandidateReport::Verdict::kNoMode: return "no_mode";
    case CandidateReport::Verdict::kImprobable: return "improbable";
    case CandidateReport::Verdict::kAreaCheck: return "area_check";
    case CandidateReport::Verdict::kOutcome: return "outcome";
  }
  return "unknown";
}

double log_evidence(const std::vector<Outcome>& outcomes, double log_eta) {
  if (outcomes.empty()) return 0.0;
  std::vector<double> lf;
  for (const Outcome& o : outcomes) lf.push_back(o.log_f);
  return log_sum_exp(lf) - log_eta;
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

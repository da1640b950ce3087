#include "hmt/global_map/keyframe_graph.h"

#include <Eigen/CholmodSupport>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/Sparse>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>

#include "hmt/metric_slam/scan_points.h"
#include "hmt/common/worker_pool.h"
#include "normal_equations.h"
#include "relative_pose_factor.h"

namespace hmt::global_map {
namespace {

// As in optimize_poses(): a Gauss-Newton step of the reweighted problem is
// a descent direction of the robust cost, so some fraction of it lowers the
// cost unless the estimate is already at a minimum to rounding.
constexpr int kMaxStepHalvings = 10;
// The smallest eigenvalue of a match's information kept when it is turned
// into a covariance: a match along a featureless corridor pins nothing down
// along it, and its covariance there is then this large rather than infinite.
constexpr double kMinInformation = 1e-6;

enum class Kind { kInArea, kConsecutive, kArc, kMatch };

struct Edge {
  int from = 0;  // variable indices
  int to = 0;
  Pose2D mean;   // pose of `to` seen from `from`
  Eigen::Matrix3d information;
  Kind kind = Kind::kInArea;
  bool robust() const { return kind == Kind::kArc || kind == Kind::kMatch; }
};

Eigen::Matrix3d diagonal_information(double std_xy, double std_theta) {
  return Eigen::Vector3d(1.0 / (std_xy * std_xy), 1.0 / (std_xy * std_xy),
                         1.0 / (std_theta * std_theta))
      .asDiagonal();
}

Eigen::Vector3d residual(const Edge& e, const std::vector<Pose2D>& x) {
  return relative_pose_residual(x[e.from], x[e.to], e.mean);
}

// rho(s) and its derivative w(s) = rho'(s), the weight of the reweighted
// least squares, of a squared Mahalanobis distance s. Huber:
// rho = 2 k sqrt(s) - k^2 beyond k^2; dynamic covariance scaling (Agarwal
// et al. 2013): rho = phi (3 s - phi) / (phi + s) beyond phi, whose weight
// (2 phi / (phi + s))^2 is the square of DCS's scaling factor. Both equal s
// (weight 1) inside the threshold, and both are continuous with their
// derivatives there.
struct Robust {
  double rho;
  double weight;
};

Robust robustify(double s, const Edge& e, const KeyframeGraphOptions& opt) {
  const double t = opt.robust_chi2;
  if (!e.robust() || s <= t) return {s, 1.0};
  if (opt.kernel == RobustKernel::kHuber) {
    const double k = std::sqrt(t), r = std::sqrt(s);
    return {2.0 * k * r - t, k / r};
  }
  const double scale = 2.0 * t / (t + s);
  return {t * (3.0 * s - t) / (t + s), scale * scale};
}

double cost_of(const std::vector<Edge>& edges, const std::vector<Pose2D>& x,
               const KeyframeGraphOptions& opt) {
  double sum = 0.0;
  for (const Edge& e : edges) {
    const Eigen::Vector3d r = residual(e, x);
    sum += robustify(r.dot(e.information * r), e, opt).rho;
  }
  return sum;
}

// The pattern of H for `edges`; column[v]: first column of variable v, -1
// for the fixed root.
NormalEquations pattern_of(const std::vector<Edge>& edges, const std::vector<int>& column,
                           int unknowns) {
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(edges.size());
  for (const Edge& e : edges)
    pairs.emplace_back(column[static_cast<size_t>(e.from)], column[static_cast<size_t>(e.to)]);
  return NormalEquations(unknowns, pairs);
}

// H and g of `edges` linearised at x, into `eq` (built by pattern_of()).
void linearise(const std::vector<Edge>& edges, const std::vector<Pose2D>& x,
               const KeyframeGraphOptions& opt, NormalEquations* eq) {
  eq->clear();
  for (size_t k = 0; k < edges.size(); ++k) {
    const Edge& e = edges[k];
    const LinearisedRelativePose l = linearise_relative_pose(x[e.from], x[e.to], e.mean);
    const double w = robustify(l.residual.dot(e.information * l.residual), e, opt).weight;
    eq->add(k, l, w * e.information);
  }
}

std::vector<Pose2D> moved(const std::vector<Pose2D>& x, const std::vector<int>& column,
                          const Eigen::VectorXd& step) {
  std::vector<Pose2D> out = x;
  for (size_t v = 0; v < x.size(); ++v) {
    const int k = column[v];
    if (k < 0) continue;
    out[v] = Pose2D(x[v].x + step(k), x[v].y + step(k + 1), wrap_angle(x[v].theta + step(k + 2)));
  }
  return out;
}

// The log steps the visits cover: which visit owns each (the latest that
// holds it, so the step a switch shares belongs to the visit it starts),
// and the robot's motion from one step to the next.
class PathTable {
 public:
  PathTable(const std::vector<AreaVisit>& visits, const StepSource& steps)
      : visits_(visits), steps_(steps) {
    for (const AreaVisit& v : visits) {
      if (v.poses.empty()) continue;
      begin_ = std::min(begin_, v.first_step);
      end_ = std::max(end_, v.first_step + v.poses.size());
    }
    if (begin_ >= end_) begin_ = end_ = 0;
    owner_.assign(end_ - begin_, -1);
    for (size_t i = 0; i < visits.size(); ++i)
      for (size_t k = 0; k < visits[i].poses.size(); ++k)
        owner_[visits[i].first_step + k - begin_] = static_cast<int>(i);
  }

  int owner(uint64_t step) const {
    return step >= begin_ && step < end_ ? owner_[step - begin_] : -1;
  }
  bool holds(int visit, uint64_t step) const {
    if (visit < 0) return false;
    const AreaVisit& v = visits_[static_cast<size_t>(visit)];
    return step >= v.first_step && step < v.first_step + v.poses.size();
  }
  const Pose2D& pose(int visit, uint64_t step) const {
    const AreaVisit& v = visits_[static_cast<size_t>(visit)];
    return v.poses[step - v.first_step];
  }
  // The pose at step + 1 seen from the pose at step: from a visit that holds
  // both (the in-area path), else the log's odometry.
  Pose2D motion(uint64_t step) const {
    for (const int v : {owner(step + 1), owner(step)})
      if (holds(v, step) && holds(v, step + 1)) return pose(v, step + 1) - pose(v, step);
    const LogStep* s = steps_(step + 1);
    return s && s->has_odometry ? s->odometry_increment : Pose2D();
  }

 private:
  const std::vector<AreaVisit>& visits_;
  const StepSource& steps_;
  uint64_t begin_ = UINT64_MAX;
  uint64_t end_ = 0;
  std::vector<int> owner_;
};

// Keyframe nodes: at the first step of each visit that the visit owns and
// the log holds, then every keyframe_distance / keyframe_angle of motion.
std::vector<KeyframeNode> select_nodes(const std::vector<AreaVisit>& visits,
                                       const PathTable& table, const StepSource& steps,
                                       const KeyframeGraphOptions& opt) {
  std::vector<KeyframeNode> nodes;
  for (size_t i = 0; i < visits.size(); ++i) {
    const AreaVisit& v = visits[i];
    std::optional<Pose2D> last;
    for (size_t k = 0; k < v.poses.size(); ++k) {
      const uint64_t step = v.first_step + k;
      if (table.owner(step) != static_cast<int>(i) || !steps(step)) continue;
      if (last && within_spacing(v.poses[k] - *last, opt.keyframe_distance, opt.keyframe_angle))
        continue;
      last = v.poses[k];
      nodes.push_back({v.area, i, step, v.poses[k], Pose2D()});
    }
  }
  return nodes;
}

struct Motion {
  Pose2D relative;
  double distance = 0.0;
  double rotation = 0.0;  // sum of |turns|
};

Motion motion_between(const PathTable& table, uint64_t from, uint64_t to) {
  Motion m;
  for (uint64_t s = from; s < to; ++s) {
    const Pose2D d = table.motion(s);
    m.relative = m.relative + d;
    m.distance += d.norm();
    m.rotation += std::fabs(d.theta);
  }
  return m;
}

// A keyframe's match in one area, as an earlier round left it: the start
// it was matched from, and the result (no information when the match
// explained too little of the scan or its Hessian was unusable).
struct PastMatch {
  int area = 0;  // variable index
  Pose2D start;
  Pose2D result;
  std::optional<Eigen::Matrix3d> information;
};

// The axis-aligned box of an area's grid placed at `pose`.
struct Box {
  double min_x, min_y, max_x, max_y;
  bool holds(const Pose2D& p) const {
    return p.x >= min_x && p.x <= max_x && p.y >= min_y && p.y <= max_y;
  }
};

std::optional<Box> global_box(const grid::OccupancyGrid& g, const Pose2D& pose) {
  grid::CellIndex lo, hi;
  if (!g.bounds(&lo, &hi)) return std::nullopt;
  const double r = g.resolution();
  Box b{INFINITY, INFINITY, -INFINITY, -INFINITY};
  for (const double x : {lo.x * r, (hi.x + 1) * r})
    for (const double y : {lo.y * r, (hi.y + 1) * r}) {
      const Point2D p = pose.transform({x, y});
      b.min_x = std::min(b.min_x, p.x);
      b.min_y = std::min(b.min_y, p.y);
      b.max_x = std::max(b.max_x, p.x);
      b.max_y = std::max(b.max_y, p.y);
    }
  return b;
}

// The information of diag(std_xy^2, std_xy^2, std_theta^2) + extra.
Eigen::Matrix3d widened_information(double std_xy, double std_theta,
                                    const Eigen::Matrix3d& extra) {
  Eigen::Matrix3d cov = Eigen::Vector3d(std_xy * std_xy, std_xy * std_xy,
                                        std_theta * std_theta).asDiagonal();
  cov += 0.5 * (extra + extra.transpose());
  return cov.inverse();
}

// The information of a match: the matcher's Hessian divided by the
// inflation, turned into a covariance (directions it does not constrain
// kept finite), plus the floor.
std::optional<Eigen::Matrix3d> match_information(const Eigen::Matrix3d& hessian,
                                                 const KeyframeGraphOptions& opt) {
  const Eigen::Matrix3d H = 0.5 * (hessian + hessian.transpose()) / opt.match_inflation;
  if (!H.allFinite()) return std::nullopt;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(H);
  const Eigen::Vector3d inv = es.eigenvalues().cwiseMax(kMinInformation).cwiseInverse();
  Eigen::Matrix3d cov = es.eigenvectors() * inv.asDiagonal() * es.eigenvectors().transpose();
  cov.diagonal() += Eigen::Vector3d(opt.match_std_xy * opt.match_std_xy,
                                    opt.match_std_xy * opt.match_std_xy,
                                    opt.match_std_theta * opt.match_std_theta);
  cov = 0.5 * (cov + cov.transpose());
  if (!topology::is_positive_definite(cov)) return std::nullopt;
  return Eigen::Matrix3d(cov.inverse());
}

class Graph {
 public:
  Graph(const topology::HmtMap& map, const std::vector<AreaVisit>& visits,
        const StepSource& steps, const GlobalPoses& initial, const KeyframeGraphOptions& opt,
        const metric_slam::MatcherOptions& matcher_opt, int threads,
        const std::vector<OutlierArc>& excluded)
      : map_(map), visits_(visits), steps_(steps), opt_(opt), matcher_(matcher_opt),
        table_(visits, steps), pool_(WorkerPool::threads_for(threads)) {
    for (const OutlierArc& o : excluded)
      excluded_.insert({std::min(o.from, o.to), std::max(o.from, o.to)});
    if (!map.has_area(initial.root) || !initial.poses.count(initial.root))
      throw std::invalid_argument("optimize_keyframe_graph: unknown root area " +
                                  std::to_string(initial.root));
    root_ = initial.root;
    for (const AreaVisit& v : visits)
      if (!map.has_area(v.area))
        throw std::invalid_argument("optimize_keyframe_graph: a visit to unknown area " +
                                    std::to_string(v.area));
    nodes_ = select_nodes(visits, table_, steps, opt);
    if (nodes_.empty())
      throw std::invalid_argument("optimize_keyframe_graph: the path has no keyframe");
    // Area variables: every area with an initial pose, and every area visited.
    std::map<AreaId, int> areas;
    for (const auto& kv : initial.poses) areas[kv.first] = 0;
    for (const KeyframeNode& n : nodes_) areas[n.area] = 0;
    for (auto& kv : areas) {
      kv.second = static_cast<int>(area_ids_.size());
      area_ids_.push_back(kv.first);
    }
    area_var_ = std::move(areas);
    for (const AreaId id : initial.unreachable)
      if (!area_var_.count(id)) unreachable_.push_back(id);
    build_fixed_edges();
    initialise(initial);
  }

  KeyframeGraph solve() {
    const auto t0 = std::chrono::steady_clock::now();
    KeyframeGraphReport& r = report_;
    r.area_nodes = area_ids_.size();
    r.keyframe_nodes = nodes_.size();
    std::vector<int> column(x_.size(), -1);
    int unknowns = 0;
    for (size_t v = 0; v < x_.size(); ++v)
      if (static_cast<int>(v) != area_var_.at(root_)) {
        column[v] = unknowns;
        unknowns += 3;
      }
    Cholesky cholesky;
    std::vector<Edge> edges;
    std::optional<NormalEquations> eq;  // this round's pattern
    // The keyframes' matches in their own areas (match_own_area) join in
    // the last round, or in the round after the estimate settled: a
    // refinement at the estimate the other constraints found. From the
    // first round they hold each area's shape while the loops are still
    // being closed, and the loops' error goes into the joints between
    // areas (docs/measurements.md).
    const bool refine_in_own_areas = opt_.match && opt_.match_own_area;
    for (int round = 0; round < opt_.rounds; ++round) {
      const bool own_areas =
          refine_in_own_areas && (round == opt_.rounds - 1 || r.converged);
      const std::vector<Pose2D> before_round = x_;
      edges = fixed_;
      if (opt_.match) add_matches(own_areas, &edges);
      ++r.rounds;
      double cost = cost_of(edges, x_, opt_);
      if (round == 0) r.initial_cost = cost;
      eq.reset();  // last round's pattern freed before this one is built
      eq.emplace(pattern_of(edges, column, unknowns));
      cholesky.analyzePattern(eq->H());
      for (int it = 0; it < opt_.max_iterations; ++it) {
        linearise(edges, x_, opt_, &*eq);
        factorize(cholesky, eq->H(), "optimize_keyframe_graph");
        const Eigen::VectorXd step = cholesky.solve(-eq->g());
        ++r.iterations;
        const double before = cost;
        if (!take_step(edges, column, step, &cost) ||
            before - cost <= opt_.relative_tolerance * before)
          break;
      }
      r.final_cost = cost;
      largest_move(before_round, &r.last_round_move_xy, &r.last_round_move_theta);
      r.converged = r.last_round_move_xy <= opt_.round_tolerance &&
                    r.last_round_move_theta <= opt_.round_tolerance;
      if (own_areas || (r.converged && !refine_in_own_areas)) break;
    }
    // The last round's constraints, counted and used for the covariances.
    for (const Edge& e : edges) {
      switch (e.kind) {
        case Kind::kInArea: ++r.in_area; break;
        case Kind::kConsecutive: ++r.consecutive; break;
        case Kind::kArc: ++r.arcs; break;
        case Kind::kMatch: ++r.matches; break;
      }
      const Eigen::Vector3d res = residual(e, x_);
      if (e.robust() && res.dot(e.information * res) > opt_.robust_chi2) ++r.down_weighted;
    }
    KeyframeGraph out;
    out.areas.root = root_;
    out.areas.unreachable = unreachable_;
    linearise(edges, x_, opt_, &*eq);
    factorize(cholesky, eq->H(), "optimize_keyframe_graph");
    for (size_t a = 0; a < area_ids_.size(); ++a) {
      topology::PoseGaussian g(x_[a], Eigen::Matrix3d::Zero());
      const int k = column[a];
      if (k >= 0) {
        Eigen::MatrixXd unit = Eigen::MatrixXd::Zero(unknowns, 3);
        unit.block<3, 3>(k, 0).setIdentity();
        const Eigen::Matrix3d block = cholesky.solve(unit).block<3, 3>(k, 0);
        g.cov = 0.5 * (block + block.transpose());
        if (!topology::is_positive_definite(g.cov))
          throw std::runtime_error("optimize_keyframe_graph: the covariance of area " +
                                   std::to_string(area_ids_[a]) + " is not positive definite");
      }
      out.areas.poses.emplace(area_ids_[a], g);
    }
    out.nodes = nodes_;
    for (size_t i = 0; i < nodes_.size(); ++i) out.nodes[i].global = x_[area_ids_.size() + i];
    r.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    out.report = r;
    return out;
  }

 private:
  int node_var(size_t i) const { return static_cast<int>(area_ids_.size() + i); }

  // The blind error of keyframe i's pose in its area (zero for most).
  Eigen::Matrix3d blind_of(size_t i) const {
    const KeyframeNode& n = nodes_[i];
    const AreaVisit& v = visits_[n.visit];
    return v.blind.empty() ? Eigen::Matrix3d::Zero()
                           : v.blind[static_cast<size_t>(n.step - v.first_step)];
  }

  void build_fixed_edges() {
    blind_.assign(nodes_.size(), 0);
    for (size_t i = 0; i < nodes_.size(); ++i) {
      const KeyframeNode& n = nodes_[i];
      const Eigen::Matrix3d blind = blind_of(i);
      blind_[i] = !blind.isZero(0.0);
      // (a) the keyframe in its area's frame.
      const double d = n.in_area.norm();
      Edge a;
      a.from = area_var_.at(n.area);
      a.to = node_var(i);
      a.mean = n.in_area;
      const double axy = opt_.in_area_std_xy + opt_.in_area_std_xy_per_metre * d;
      const double ath = opt_.in_area_std_theta + opt_.in_area_std_theta_per_metre * d;
      a.information = blind_[i] ? widened_information(axy, ath, blind)
                                : diagonal_information(axy, ath);
      a.kind = Kind::kInArea;
      fixed_.push_back(a);
      // (b) the motion from the previous keyframe.
      if (i == 0) continue;
      const Motion m = motion_between(table_, nodes_[i - 1].step, n.step);
      Edge b;
      b.from = node_var(i - 1);
      b.to = node_var(i);
      b.mean = m.relative;
      // Across blind steps too: their motion is the odometry's, whose error
      // is a fraction of the motion model's noise (wide on purpose, so that
      // the proposal reaches the true pose). Widened by that noise, the
      // motion held a 200-scan blind stretch of Intel no better than its
      // ties to the area, and it stayed as dead-reckoned (6.55 m position
      // RMSE over the log against 4.73 m).
      b.information = diagonal_information(
          opt_.step_std_xy + opt_.step_std_xy_per_metre * m.distance,
          opt_.step_std_theta + opt_.step_std_theta_per_metre * m.distance +
              opt_.step_std_theta_per_radian * m.rotation);
      b.kind = Kind::kConsecutive;
      fixed_.push_back(b);
    }
    // (c) the arcs between areas that are variables.
    for (const auto& kv : map_.arcs()) {
      if (excluded_.count(kv.first)) continue;  // a closure the area fit switched off
      const auto from = area_var_.find(kv.first.first), to = area_var_.find(kv.first.second);
      if (from == area_var_.end() || to == area_var_.end()) continue;
      Edge c;
      c.from = from->second;
      c.to = to->second;
      c.mean = kv.second.pose.mean;
      c.information = kv.second.pose.cov.inverse();
      c.kind = Kind::kArc;
      fixed_.push_back(c);
    }
  }

  // Areas at their initial poses, keyframes at their area's pose composed
  // with their in-area pose; an area without an initial pose is placed from
  // the keyframe before its first one along the path (or after, for areas
  // visited before any placed one).
  void initialise(const GlobalPoses& initial) {
    const size_t A = area_ids_.size();
    x_.assign(A + nodes_.size(), Pose2D());
    std::vector<char> placed(A, 0);
    for (size_t a = 0; a < A; ++a) {
      const auto it = initial.poses.find(area_ids_[a]);
      if (it != initial.poses.end()) {
        x_[a] = it->second.mean;
        placed[a] = 1;
      }
    }
    std::vector<char> node_placed(nodes_.size(), 0);
    auto place = [&](size_t i, std::optional<Pose2D> from_neighbour) {
      const int a = area_var_.at(nodes_[i].area);
      if (placed[static_cast<size_t>(a)]) {
        x_[A + i] = x_[static_cast<size_t>(a)] + nodes_[i].in_area;
      } else if (from_neighbour) {
        x_[A + i] = *from_neighbour;
        x_[static_cast<size_t>(a)] = *from_neighbour + nodes_[i].in_area.inverse();
        placed[static_cast<size_t>(a)] = 1;
      } else {
        return;
      }
      node_placed[i] = 1;
    };
    for (size_t i = 0; i < nodes_.size(); ++i) {
      std::optional<Pose2D> prev;
      if (i > 0 && node_placed[i - 1])
        prev = x_[A + i - 1] + motion_between(table_, nodes_[i - 1].step, nodes_[i].step).relative;
      place(i, prev);
    }
    for (size_t i = nodes_.size(); i-- > 0;) {
      if (node_placed[i]) continue;
      std::optional<Pose2D> next;
      if (i + 1 < nodes_.size() && node_placed[i + 1])
        next = x_[A + i + 1] +
               motion_between(table_, nodes_[i].step, nodes_[i + 1].step).relative.inverse();
      place(i, next);
    }
  }

  // (d) every keyframe's scan in every other area whose box (at the
  // current estimate) holds the keyframe, and in its own area if
  // `own_areas`.
  // Keyframes are matched in parallel, each into its own slot, and the
  // slots joined in keyframe order, so the constraints do not depend on the
  // number of threads.
  void add_matches(bool own_areas, std::vector<Edge>* edges) {
    const size_t A = area_ids_.size();
    std::vector<std::optional<Box>> boxes(A);
    for (size_t a = 0; a < A; ++a)
      if (const auto& g = map_.area(area_ids_[a]).map) boxes[a] = global_box(*g, x_[a]);
    std::vector<std::vector<Edge>> found(nodes_.size());
    std::vector<size_t> tried(nodes_.size(), 0), reused(nodes_.size(), 0);
    past_.resize(nodes_.size());
    pool_.parallel_for(nodes_.size(), [&](size_t i) {
      match_node(i, boxes, own_areas, &found[i], &tried[i], &reused[i]);
    });
    report_.matches_tried = 0;
    report_.matches_reused = 0;
    for (size_t i = 0; i < nodes_.size(); ++i) {
      report_.matches_tried += tried[i];
      report_.matches_reused += reused[i];
      edges->insert(edges->end(), found[i].begin(), found[i].end());
    }
  }

  // Matches keyframe i in every other area whose box holds it (and in its
  // own if `own_areas`), into `out`; its slot of past_ (written by this
  // call only) keeps the matches for the next round.
  void match_node(size_t i, const std::vector<std::optional<Box>>& boxes, bool own_areas,
                  std::vector<Edge>* out, size_t* tried, size_t* reused) {
    const size_t A = area_ids_.size();
    const metric_slam::MatcherOptions& mo = matcher_.options();
    const Pose2D& g = x_[A + i];
    const LogStep* step = steps_(nodes_[i].step);
    if (!step) return;
    std::vector<PastMatch> past;
    past.swap(past_[i]);
    // The scan's points, prepared once for all the areas (their grids share
    // a resolution; prepared again for one that does not).
    std::optional<metric_slam::MatchScan> ready;
    double pts_resolution = 0.0;
    for (size_t a = 0; a < A; ++a) {
      // Its own area's grid was drawn at the very poses a blind stretch put
      // it at: matched there, it would hold the stretch as it is.
      if (area_ids_[a] == nodes_[i].area && (!own_areas || blind_[i])) continue;
      if (!boxes[a] || !boxes[a]->holds(g)) continue;
      const grid::OccupancyGrid& grid = *map_.area(area_ids_[a]).map;
      if (grid.resolution() != pts_resolution) {
        ready.emplace(
            metric_slam::prepare_scan(step->scan, mo.max_range, mo.beam_skip, grid.resolution()),
            mo);
        pts_resolution = grid.resolution();
      }
      const metric_slam::ScanPoints& pts = ready->points();
      if (pts.hit.empty()) continue;
      ++*tried;
      const Pose2D guess = x_[a].inverse() + g;
      PastMatch match;
      if (const PastMatch* kept = reusable(past, static_cast<int>(a), guess)) {
        match = *kept;
        ++*reused;
      } else {
        match = {static_cast<int>(a), guess, Pose2D(), std::nullopt};
        metric_slam::MatchScore score;
        Eigen::Matrix3d hessian;
        match.result = matcher_.optimize(grid, guess, *ready, &score, &hessian);
        if (score.matched >= opt_.match_min_ratio * static_cast<double>(pts.hit.size()))
          match.information = match_information(hessian, opt_);
      }
      past_[i].push_back(match);
      if (!match.information) continue;
      const Pose2D moved_by = match.result - guess;
      if (moved_by.norm() > opt_.match_gate_xy || std::fabs(moved_by.theta) > opt_.match_gate_theta)
        continue;
      Edge e;
      e.from = static_cast<int>(a);
      e.to = node_var(i);
      e.mean = match.result;
      e.information = *match.information;
      e.kind = Kind::kMatch;
      out->push_back(e);
    }
  }

  // The past match in area `a` if its start lies within the matcher's finest
  // step of `guess`; nullptr when there is none (or reuse is off).
  const PastMatch* reusable(const std::vector<PastMatch>& past, int a, const Pose2D& guess) const {
    if (!opt_.match_reuse) return nullptr;
    const auto p = std::find_if(past.begin(), past.end(),
                                [a](const PastMatch& m) { return m.area == a; });
    if (p == past.end()) return nullptr;
    const Pose2D d = guess - p->start;
    const bool same_start = d.norm() < matcher_.finest_linear_step() &&
                            std::fabs(d.theta) < matcher_.finest_angular_step();
    return same_start ? &*p : nullptr;
  }

  // The largest distance and the largest heading change of a keyframe from
  // `x` to the current estimate.
  void largest_move(const std::vector<Pose2D>& x, double* xy, double* theta) const {
    *xy = 0.0;
    *theta = 0.0;
    for (size_t v = area_ids_.size(); v < x_.size(); ++v) {
      *xy = std::max(*xy, std::hypot(x_[v].x - x[v].x, x_[v].y - x[v].y));
      *theta = std::max(*theta, std::fabs(wrap_angle(x_[v].theta - x[v].theta)));
    }
  }

  bool take_step(const std::vector<Edge>& edges, const std::vector<int>& column,
                 const Eigen::VectorXd& step, double* cost) {
    double fraction = 1.0;
    for (int k = 0; k <= kMaxStepHalvings; ++k, fraction *= 0.5) {
      std::vector<Pose2D> candidate = moved(x_, column, fraction * step);
      const double c = cost_of(edges, candidate, opt_);
      if (c <= *cost) {
        x_ = std::move(candidate);
        *cost = c;
        return true;
      }
    }
    return false;
  }

  const topology::HmtMap& map_;
  std::set<std::pair<AreaId, AreaId>> excluded_;  // (lo, hi), as the map keys its arcs
  const std::vector<AreaVisit>& visits_;
  const StepSource& steps_;
  const KeyframeGraphOptions& opt_;
  metric_slam::ScanMatcher matcher_;
  PathTable table_;
  WorkerPool pool_;
  AreaId root_ = topology::kNoArea;
  std::vector<KeyframeNode> nodes_;
  std::vector<AreaId> area_ids_;  // ascending; variable a is area_ids_[a]
  std::map<AreaId, int> area_var_;
  std::vector<AreaId> unreachable_;
  std::vector<Edge> fixed_;  // (a), (b), (c): the same in every round
  std::vector<char> blind_;  // per keyframe: its pose carries a blind error
  std::vector<std::vector<PastMatch>> past_;  // per keyframe, the last round's matches
  std::vector<Pose2D> x_;    // areas, then keyframes
  KeyframeGraphReport report_;
};

}  // namespace

KeyframeGraph optimize_keyframe_graph(const topology::HmtMap& map,
                                      const std::vector<AreaVisit>& visits,
                                      const StepSource& steps, const GlobalPoses& initial,
                                      const KeyframeGraphOptions& options,
                                      const metric_slam::MatcherOptions& matcher,
                                      int threads, const std::vector<OutlierArc>& excluded) {
  Graph graph(map, visits, steps, initial, options, matcher, threads, excluded);
  return graph.solve();
}

std::vector<uint64_t> keyframe_steps(const std::vector<AreaVisit>& visits,
                                     const StepSource& steps,
                                     const KeyframeGraphOptions& options) {
  const PathTable table(visits, steps);
  std::vector<uint64_t> out;
  for (const KeyframeNode& n : select_nodes(visits, table, steps, options)) out.push_back(n.step);
  return out;
}

}  // namespace hmt::global_map

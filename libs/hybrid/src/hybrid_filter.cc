#include "hmt/hybrid/hybrid_filter.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>

#include "hmt/common/error.h"
#include "hmt/common/log_sum_exp.h"
#include "hmt/common/random.h"
#include "hmt/tsbi/observations.h"

namespace hmt::hybrid {
namespace {

using topology::AreaId;
using topology::PoseGaussian;



// Weighted covariance of poses around `mean` (angles unwrapped next to it).
Eigen::Matrix3d spread(const std::vector<Pose2D>& poses, const std::vector<double>& w,
                       const Pose2D& mean) {
  Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < poses.size(); ++i) {
    const Eigen::Vector3d d = topology::difference(poses[i], mean);
    c += w[i] * d * d.transpose();
  }
  return 0.5 * (c + c.transpose());
}

// The particles' current poses (last path entry: the step just processed).
std::vector<Pose2D> current_poses(const metric_slam::GridRbpf& f) {
  std::vector<Pose2D> out;
  for (const auto& p : f.particles()) out.push_back(p.path.back());
  return out;
}

}  // namespace

HybridFilter::HybridFilter(const HmtOptions& options)
    : opt_(options),
      pool_(std::make_shared<metric_slam::WorkerPool>(
          metric_slam::WorkerPool::threads_for(options.rbpf.threads))),
      aam_(options.area),
      tsbi_(options.tsbi, options.rbpf.matcher, options.rbpf.likelihood_gain, options.area,
            pool_) {}

void HybridFilter::start(const LogStep& step) {
  Hypothesis h{metric_slam::GridRbpf(opt_.rbpf, pool_)};
  h.id = next_hypothesis_id_++;
  h.filter.reseed(mix_seed(opt_.rbpf.seed ^ mix_seed(h.id)));
  // Areas are numbered from 1, as in the paper's figures.
  topology::ReferenceFrame frame;
  frame.created_step = 0;
  frame.created_time = step.timestamp;
  h.map.add_area(1, frame);
  h.topo.path = {{1, 0}};
  h.filter.process(step);
  hyps_.push_back(std::move(h));
}

void HybridFilter::process(const LogStep& step) {
  step_ = stats_.steps++;
  if (hyps_.empty()) {
    start(step);
  } else {
    for (Hypothesis& h : hyps_) {
      h.filter.process(step);
      h.topo.log_weight += h.filter.last_log_evidence();
    }
    normalise_and_prune();
  }
  add_keyframe(step);
  accept_if_dominant();
}

void HybridFilter::add_keyframe(const LogStep& step) {
  const Hypothesis& h = best();
  const Pose2D pose = h.aam_from_area + h.filter.best().path.back();
  if (has_keyframe_) {
    const Pose2D d = pose - last_keyframe_pose_;
    if (d.norm() < opt_.hybrid.keyframe_distance &&
        std::fabs(d.theta) < opt_.hybrid.keyframe_angle)
      return;
  }
  size_t returns = 0;
  for (uint8_t v : step.scan.valid) returns += v != 0;
  if (returns < 20) return;  // senses too little to overlap with anything
  has_keyframe_ = true;
  last_keyframe_pose_ = pose;
  keyframes_.push_back({step_, step.scan});
  ++stats_.keyframes;
  for (Hypothesis& hh : hyps_)
    hh.map.add_keyframe(hh.current_area(), {hh.filter.best().path.back(), step.scan});
  aam_.add_keyframe(area::Keyframe{area::PoseGaussian(pose), step.scan});
  const area::AreaDecision decision = aam_.update();
  if (decision.new_area) on_new_area(decision, step);
}

void HybridFilter::on_new_area(const area::AreaDecision& decision, const LogStep& step) {
  ++stats_.new_area_events;
  const std::vector<double> before = probabilities();
  std::vector<Hypothesis> parents;
  parents.swap(hyps_);
  for (size_t i = 0; i < parents.size(); ++i) {
    std::vector<Hypothesis> children = branch(std::move(parents[i]), decision, step);
    transitions_.back().parent_probability = before[i];
    for (auto& c : children) hyps_.push_back(std::move(c));
  }
  normalise_and_prune();
}

std::vector<Hypothesis> HybridFilter::branch(Hypothesis parent,
                                             const area::AreaDecision& decision,
                                             const LogStep& step) {
  const AreaId c = parent.current_area();
  const metric_slam::GridRbpf& f = parent.filter;
  const size_t best = f.best_index();
  const metric_slam::Particle& bp = f.particles()[best];
  const Pose2D now = bp.path.back();
  const std::vector<double> w = f.weights();

  // The latest observations: the new area's keyframes seen from the best
  // particle's path (those taken in this area; earlier ones are in no path).
  std::vector<metric_slam::SeedScan> seeds;
  std::vector<tsbi::PosedScan> posed;
  for (int k : decision.new_area_keyframes) {
    const KeyframeRecord& kf = keyframes_[static_cast<size_t>(k)];
    if (kf.step < parent.area_start_step) continue;
    const size_t idx = static_cast<size_t>(kf.step - parent.area_start_step);
    if (idx >= bp.path.size()) continue;
    seeds.push_back({idx, &kf.scan});
    posed.push_back({bp.path[idx], &kf.scan});
  }
  const auto& ro = opt_.rbpf;
  const tsbi::Observations obs = tsbi::gather_observations(
      posed, now, ro.matcher.max_range, ro.resolution, opt_.tsbi.max_points);

  // The robot in the current area: the best particle, with the particles'
  // spread (floored: after resampling it can be nearly zero).
  PoseGaussian robot(now, spread(current_poses(f), w, now));
  robot.cov.diagonal() += Eigen::Vector3d(1e-4, 1e-4, 1e-5);

  TransitionEvent ev;
  ev.step = step_;
  ev.time = step.timestamp;
  ev.hypothesis = parent.id;
  ev.from_area = c;
  ev.outcomes = tsbi_.evaluate(parent.map, c, robot, obs);

  // The area being left is archived under this hypothesis, with the best
  // particle's map and path.
  parent.map.archive_map(c, bp.map);
  auto seg = std::make_shared<TrajectorySegment>();
  seg->area = c;
  seg->first_step = parent.area_start_step;
  seg->poses = bp.path;
  parent.trajectory.push_back(std::move(seg));
  const Pose2D aam_now = parent.aam_from_area + now;

  // Outcomes too improbable to follow get no child; the others share the
  // parent's weight in proportion.
  const std::vector<size_t> follow = tsbi::probable_outcomes(ev.outcomes, opt_.tsbi.min_probability);
  double followed = 0.0;
  for (size_t k : follow) followed += ev.outcomes[k].probability;
  ev.children.assign(ev.outcomes.size(), kNoChild);
  ev.entered.assign(ev.outcomes.size(), topology::kNoArea);
  std::vector<Hypothesis> children;
  for (size_t f = 0; f < follow.size(); ++f) {
    const size_t k = follow[f];
    const tsbi::Outcome& o = ev.outcomes[k];
    // The last outcome takes the parent itself; the others copy it (maps and
    // area tables are shared copy-on-write).
    Hypothesis child = f + 1 == follow.size() ? std::move(parent) : parent;
    child.id = next_hypothesis_id_++;
    child.filter.reseed(mix_seed(opt_.rbpf.seed ^ mix_seed(child.id)));
    child.topo.log_weight += std::log(o.probability / followed);
    child.area_start_step = step_;
    AreaId entered;
    if (o.is_new()) {
      const std::vector<Pose2D> origins = child.filter.start_new_area(seeds, best);
      PoseGaussian arc(origins[best], spread(origins, w, origins[best]));
      const double len = origins[best].norm();
      const double sxy = opt_.hybrid.arc_std_xy + opt_.hybrid.arc_std_xy_per_metre * len;
      const double sth = opt_.hybrid.arc_std_theta + opt_.hybrid.arc_std_theta_per_metre * len;
      arc.cov.diagonal() += Eigen::Vector3d(sxy * sxy, sxy * sxy, sth * sth);
      entered = child.map.next_area_id();
      topology::ReferenceFrame frame;
      frame.parent = c;
      frame.origin_in_parent = origins[best];
      frame.created_step = step_;
      frame.created_time = step.timestamp;
      child.map.add_area(entered, frame);
      child.map.add_arc_measurement(c, entered, arc);
      child.aam_from_area = child.aam_from_area + origins[best];
    } else {
      entered = o.area;
      // Each particle's pose in the known area: a draw from the match
      // posterior (what the observations say, not where the particle was).
      Random rng(mix_seed(opt_.rbpf.seed ^ mix_seed(step_ * 1000003ULL + child.id)));
      std::vector<Pose2D> poses;
      for (size_t i = 0; i < child.filter.particles().size(); ++i)
        poses.push_back(topology::sample(o.robot, rng));
      child.filter.load_area(*child.map.area(o.area).map, poses);
      tlca::ClosureRecord rec;
      rec.from = c;
      rec.to = o.area;
      rec.step = step_;
      if (const topology::Arc* a = child.map.find_arc(c, o.area)) rec.arc_before = *a;
      // gamma's frame in c's frame: the robot in c composed with the inverse
      // of the robot in gamma.
      rec.measurement = topology::compose(robot, topology::inverse(o.robot));
      const double sxy = opt_.hybrid.arc_std_xy, sth = opt_.hybrid.arc_std_theta;
      rec.measurement.cov.diagonal() += Eigen::Vector3d(sxy * sxy, sxy * sxy, sth * sth);
      child.map.add_arc_measurement(c, o.area, rec.measurement);
      child.pending_closures.push_back(rec);
      child.aam_from_area = aam_now + o.robot.mean.inverse();
    }
    topology::enter_area(child.topo, entered, step_);
    ev.children[k] = child.id;
    ev.entered[k] = entered;
    children.push_back(std::move(child));
  }
  transitions_.push_back(std::move(ev));
  return children;
}

std::vector<double> HybridFilter::probabilities() const {
  std::vector<double> lw;
  for (const auto& h : hyps_) lw.push_back(h.topo.log_weight);
  const double z = log_sum_exp(lw);
  for (double& x : lw) x = std::exp(x - z);
  return lw;
}

const Hypothesis& HybridFilter::best() const {
  size_t b = 0;
  for (size_t i = 1; i < hyps_.size(); ++i)
    if (hyps_[i].topo.log_weight > hyps_[b].topo.log_weight) b = i;
  return hyps_[b];
}

std::map<AreaId, double> HybridFilter::position_pmf() const {
  std::vector<topology::TopologicalHypothesis> t;
  for (const auto& h : hyps_) t.push_back(h.topo);
  return topology::position_pmf(t);
}

void HybridFilter::normalise_and_prune() {
  // Keep the log weights near zero (normalised) so they never lose precision.
  std::vector<double> p = probabilities();
  for (size_t i = 0; i < hyps_.size(); ++i) hyps_[i].topo.log_weight = std::log(p[i]);
  std::vector<size_t> order(hyps_.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return p[a] > p[b]; });
  std::vector<char> keep(hyps_.size(), 0);
  for (size_t r = 0; r < order.size(); ++r)
    keep[order[r]] = r == 0 || (p[order[r]] >= opt_.hybrid.prune_probability &&
                                r < static_cast<size_t>(opt_.hybrid.max_hypotheses));
  std::vector<Hypothesis> kept;
  for (size_t i = 0; i < hyps_.size(); ++i)
    if (keep[i]) kept.push_back(std::move(hyps_[i]));
  hyps_ = std::move(kept);
  std::sort(hyps_.begin(), hyps_.end(),
            [](const Hypothesis& a, const Hypothesis& b) { return a.id < b.id; });
  p = probabilities();
  for (size_t i = 0; i < hyps_.size(); ++i) hyps_[i].topo.log_weight = std::log(p[i]);
  stats_.max_hypotheses_alive = std::max(stats_.max_hypotheses_alive, hyps_.size());
}

void HybridFilter::accept_if_dominant() {
  const std::vector<double> p = probabilities();
  const auto winner = tlca::dominant(p, opt_.tlca);
  if (!winner) {
    // No acceptance: only the history every hypothesis shares is forgotten.
    std::vector<topology::TopologicalHypothesis> t;
    for (const auto& h : hyps_) t.push_back(h.topo);
    const std::vector<topology::PathEntry> common = topology::common_prefix(t);
    if (common.size() > 1) {
      const size_t n = topology::forget_common_history(t);
      accepted_path_.insert(accepted_path_.end(), common.begin(), common.begin() + n);
      for (size_t i = 0; i < hyps_.size(); ++i) hyps_[i].topo.path = t[i].path;
      stats_.forgotten_path_entries += n;
    }
    return;
  }
  Hypothesis& w = hyps_[*winner];
  if (hyps_.size() == 1 && w.pending_closures.empty() && w.topo.path.size() <= 1) return;
  AcceptanceEvent ev;
  ev.step = step_;
  ev.hypothesis = w.id;
  ev.probability = p[*winner];
  ev.dropped = hyps_.size() - 1;
  for (const tlca::ClosureRecord& rec : w.pending_closures) {
    ev.closures.push_back(tlca::accept_closure(w.map, rec, opt_.tlca));
    ++stats_.loop_closures_accepted;
  }
  w.pending_closures.clear();
  // The accepted path is forgotten up to the current area.
  const size_t n = w.topo.path.size() - 1;
  accepted_path_.insert(accepted_path_.end(), w.topo.path.begin(), w.topo.path.begin() + n);
  w.topo.path.erase(w.topo.path.begin(), w.topo.path.begin() + n);
  stats_.forgotten_path_entries += n;
  w.topo.log_weight = 0.0;
  Hypothesis survivor = std::move(w);
  hyps_.clear();
  hyps_.push_back(std::move(survivor));
  if (ev.dropped > 0 || !ev.closures.empty()) acceptances_.push_back(std::move(ev));
}

size_t HybridFilter::map_memory_bytes() const {
  std::unordered_set<const grid::Tile*> tiles;
  for (const auto& h : hyps_) {
    for (const auto& p : h.filter.particles())
      p.map.for_each_tile([&](const grid::Tile* t) { tiles.insert(t); });
    for (AreaId id : h.map.area_ids())
      if (const auto& m = h.map.area(id).map)
        m->for_each_tile([&](const grid::Tile* t) { tiles.insert(t); });
  }
  return tiles.size() * sizeof(grid::Tile);
}

topology::HmtMap HybridFilter::final_map() const {
  const Hypothesis& h = best();
  topology::HmtMap m = h.map;
  m.archive_map(h.current_area(), h.filter.best().map);
  return m;
}

std::vector<TrajectorySegment> HybridFilter::final_trajectory() const {
  const Hypothesis& h = best();
  std::vector<TrajectorySegment> out;
  for (const auto& s : h.trajectory) out.push_back(*s);
  TrajectorySegment cur;
  cur.area = h.current_area();
  cur.first_step = h.area_start_step;
  cur.poses = h.filter.best().path;
  out.push_back(std::move(cur));
  return out;
}

}  // namespace hmt::hybrid

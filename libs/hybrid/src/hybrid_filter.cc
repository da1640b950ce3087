#include "hmt/hybrid/hybrid_filter.h"

#include <algorithm>
#include <cmath>

#include "hmt/common/error.h"
#include "hmt/common/log_sum_exp.h"
#include "hmt/common/random.h"
#include "hmt/area/keyframe.h"
#include "hmt/area/placement.h"
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
      pool_(std::make_shared<WorkerPool>(
          WorkerPool::threads_for(options.rbpf.threads))),
      topology_pool_(std::make_shared<WorkerPool>(
          WorkerPool::threads_for(options.rbpf.threads))),
      aam_(options.area),
      tsbi_(options.tsbi, options.rbpf.matcher, options.rbpf.likelihood_gain, options.area,
            topology_pool_) {}

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
  if (const std::optional<area::Keyframe> kf = metric_step(step)) {
    aam_.add_keyframe(*kf);
    const area::AreaDecision decision = aam_.update();
    if (decision.new_area) run_event(decision);
    release_keyframe_scans_before(decision.oldest_in_window);
  }
  accept_and_align();
}

void HybridFilter::finish() {
  if (hyps_.empty() || !opt_.hybrid.end_of_log_event) return;
  // An area entered at the last step holds nothing the event did not weigh.
  if (!transitions_.empty() && transitions_.back().step == step_) return;
  const area::AreaDecision decision = aam_.end_of_log();
  if (decision.new_area) {
    keep_most_probable();
    run_event(decision);
  }
  accept_and_align();
}

void HybridFilter::run_event(const area::AreaDecision& decision) {
  const std::vector<EventInput> inputs = prepare_event(decision);
  std::vector<std::vector<tsbi::CandidateReport>> considered;
  const std::vector<std::vector<tsbi::Outcome>> outcomes = evaluate(inputs, &considered);
  apply_event(decision, inputs, outcomes, &considered);
}

void HybridFilter::accept_and_align() {
  if (const std::optional<AlignmentJob> job = accept_if_dominant())
    apply_alignment(*job, align(*job));
}

std::optional<area::Keyframe> HybridFilter::metric_step(const LogStep& step) {
  step_ = stats_.steps++;
  time_ = step.timestamp;
  if (hyps_.empty()) {
    start(step);
  } else {
    // The particles of every hypothesis move in one parallel loop: a loop
    // per hypothesis would wait at its end for its slowest particle.
    std::vector<std::pair<size_t, size_t>> moves;  // (hypothesis, particle)
    for (size_t k = 0; k < hyps_.size(); ++k)
      if (hyps_[k].filter.begin_step(step))
        for (size_t i = 0; i < hyps_[k].filter.pending_moves(); ++i) moves.emplace_back(k, i);
    pool_->parallel_for(moves.size(),
                        [&](size_t j) { hyps_[moves[j].first].filter.move(moves[j].second); });
    for (Hypothesis& h : hyps_) {
      h.filter.end_step();
      h.topo.log_weight += h.filter.last_log_evidence();
    }
    normalise_and_prune();
  }
  return keyframe_due(step);
}

void HybridFilter::release_keyframe_scans_before(int id) {
  // Backwards until the first one already let go: each call frees only what
  // the last left.
  for (size_t k = std::min(static_cast<size_t>(std::max(id, 0)), keyframes_.size());
       k-- > 0 && keyframes_[k].scan;)
    keyframes_[k].scan.reset();
}

size_t HybridFilter::keyframe_scans_held() const {
  return static_cast<size_t>(std::count_if(keyframes_.begin(), keyframes_.end(),
                                           [](const KeyframeRecord& k) { return k.scan != nullptr; }));
}

std::optional<area::Keyframe> HybridFilter::keyframe_due(const LogStep& step) {
  const Hypothesis& h = best();
  const Pose2D pose = h.in_keyframes(h.filter.best().path.back());
  if (has_keyframe_) {
    if (within_spacing(pose - last_keyframe_pose_, opt_.hybrid.keyframe_distance,
                       opt_.hybrid.keyframe_angle))
      return std::nullopt;
  }
  if (!area::enough_returns(step.scan)) return std::nullopt;
  has_keyframe_ = true;
  last_keyframe_pose_ = pose;
  // Every other hypothesis has the robot here too: anchor its frame so.
  for (Hypothesis& hh : hyps_)
    if (&hh != &h)
      hh.keyframes_from_aam = pose + (hh.aam_from_area + hh.filter.best().path.back()).inverse();
  keyframes_.push_back({step_, std::make_shared<const LaserScan>(step.scan), pose});
  ++stats_.keyframes;
  // An area keeps a keyframe only where it has none within the keyframe
  // spacing (the rule above, applied against all of the area's keyframes
  // rather than the last one): a robot driving through an area again sees
  // what its keyframes from the first pass already hold, so the area's
  // keyframes stop growing once it is covered, and so do the memory and
  // TSBI's area check that reads them (the soak's later laps).
  const double kd = opt_.hybrid.keyframe_distance, ka = opt_.hybrid.keyframe_angle;
  for (Hypothesis& hh : hyps_) {
    const Pose2D at = hh.filter.best().path.back();
    if (!hh.map.has_keyframe_near(hh.current_area(), at, kd, ka))
      hh.map.add_keyframe(hh.current_area(), {at, step.scan, step_});
  }
  area::Keyframe kf{area::PoseGaussian(pose), step.scan};
  const area::PlacementOptions& po = opt_.area.placement;
  if (po.policy != area::Placement::kSso) {
    // epsilon of 003 Eq. 3: the robot's position error accumulated since
    // the current area began, per axis. Two parts, combined in quadrature:
    // the arc model's standard deviation (apply_event) over the distance
    // travelled in the area -- the travelled distance, not the displacement,
    // so that the error keeps growing when the robot turns back -- and the
    // particles' spread.
    const metric_slam::GridRbpf& f = h.filter;
    const std::vector<Pose2D>& path = f.best().path;
    const Pose2D now = path.back();
    double len = 0.0;
    for (size_t i = 1; i < path.size(); ++i) len += (path[i] - path[i - 1]).norm();
    const double sxy = opt_.hybrid.arc_floor_xy(len);
    const Eigen::Matrix3d c = spread(current_poses(f), f.weights(), now);
    kf.uncertainty = std::sqrt(sxy * sxy + 0.5 * std::max(0.0, c(0, 0) + c(1, 1)));
    kf.distinctiveness = area::scan_distinctiveness(step.scan, po);
  }
  return kf;
}

std::vector<std::pair<size_t, const HybridFilter::KeyframeRecord*>>
HybridFilter::keyframes_in_path(const area::AreaDecision& decision, uint64_t area_start_step,
                                size_t path_size) const {
  std::vector<std::pair<size_t, const KeyframeRecord*>> out;
  for (int k : decision.new_area_keyframes) {
    const KeyframeRecord& kf = keyframes_[static_cast<size_t>(k)];
    if (kf.step < area_start_step) continue;
    const size_t idx = static_cast<size_t>(kf.step - area_start_step);
    if (idx < path_size) out.emplace_back(idx, &kf);
  }
  return out;
}

std::vector<EventInput> HybridFilter::prepare_event(const area::AreaDecision& decision) const {
  const std::vector<double> p = probabilities();
  std::vector<EventInput> inputs;
  for (size_t i = 0; i < hyps_.size(); ++i) {
    const Hypothesis& h = hyps_[i];
    const metric_slam::GridRbpf& f = h.filter;
    const metric_slam::Particle& bp = f.best();
    const Pose2D now = bp.path.back();
    EventInput in;
    in.hypothesis = h.id;
    in.step = step_;
    in.time = time_;
    in.probability = p[i];
    in.from_area = h.current_area();
    in.area_start_step = h.area_start_step;
    in.map = h.map;
    // The robot in the current area: the best particle, with the particles'
    // spread (floored: after resampling it can be nearly zero).
    // The steps moved by the odometry alone (a blind laser) spread no
    // particle; their error is kept beside the spread.
    in.robot = PoseGaussian(now, spread(current_poses(f), f.weights(), now) + f.blind_cov());
    in.robot.cov.diagonal() += Eigen::Vector3d(1e-4, 1e-4, 1e-5);
    // The latest observations: the new area's keyframes seen from the best
    // particle's path (those taken in this area; earlier ones are in no path).
    std::vector<tsbi::PosedScan> posed;
    for (const auto& [idx, kf] : keyframes_in_path(decision, h.area_start_step, bp.path.size())) {
      posed.push_back({bp.path[idx], kf->scan.get()});
      in.scans.push_back(kf->scan);
    }
    const auto& ro = opt_.rbpf;
    in.observations = tsbi::gather_observations(posed, now, ro.matcher.max_range, ro.resolution,
                                                opt_.tsbi.max_points, opt_.tsbi.evidence_cell);
    inputs.push_back(std::move(in));
  }
  return inputs;
}

std::vector<std::vector<tsbi::Outcome>> HybridFilter::evaluate(
    const std::vector<EventInput>& inputs,
    std::vector<std::vector<tsbi::CandidateReport>>* considered) const {
  std::vector<tsbi::TransitionModel::Query> queries;
  for (const EventInput& in : inputs)
    queries.push_back({&in.map, in.from_area, in.robot, &in.observations});
  return tsbi_.evaluate_all(queries, considered);
}

void HybridFilter::apply_event(const area::AreaDecision& decision,
                               const std::vector<EventInput>& inputs,
                               const std::vector<std::vector<tsbi::Outcome>>& outcomes,
                               const std::vector<std::vector<tsbi::CandidateReport>>* considered) {
  if (inputs.size() != outcomes.size() || (considered && considered->size() != inputs.size()))
    throw Error(ExitCode::kInternal, "apply_event: one TSBI result per input is needed");
  ++stats_.new_area_events;
  std::vector<Hypothesis> parents;
  parents.swap(hyps_);
  // The input (and results) of each parent, if it has one: a hypothesis
  // born after the snapshot has nothing to decide.
  std::vector<size_t> input_of(parents.size(), 0);
  for (size_t i = 0; i < parents.size(); ++i)
    while (input_of[i] < inputs.size() && inputs[input_of[i]].hypothesis != parents[i].id)
      ++input_of[i];
  // Pruning is decided before any child is built, on the log weights of
  // every hypothesis the event leaves (in the order they would hold), so
  // that children it would drop at once are never built: each child copies
  // its parent's particles and loads its area's map into every one of them,
  // and an event of two hypotheses with five look-alike areas each built ten
  // sets of particles to keep four (the soak's late laps). What is kept,
  // and every weight, are the same as building them all and then pruning.
  std::vector<double> log_weights;
  std::vector<Followed> followed(parents.size());
  for (size_t i = 0; i < parents.size(); ++i) {
    if (input_of[i] == inputs.size()) {
      log_weights.push_back(parents[i].topo.log_weight);
      continue;
    }
    followed[i] = follow_outcomes(parents[i], outcomes[input_of[i]]);
    log_weights.insert(log_weights.end(), followed[i].log_weights.begin(),
                       followed[i].log_weights.end());
  }
  std::vector<double> log_p;
  const std::vector<char> keep = survivors(log_weights, &log_p);
  size_t slot = 0;
  for (size_t i = 0; i < parents.size(); ++i) {
    Hypothesis& parent = parents[i];
    if (input_of[i] == inputs.size()) {
      if (keep[slot]) {
        parent.topo.log_weight = log_p[slot];
        hyps_.push_back(std::move(parent));
      }
      ++slot;
      continue;
    }
    std::vector<std::optional<double>> child_log_p;
    for (size_t j = 0; j < followed[i].outcomes.size(); ++j, ++slot)
      child_log_p.push_back(keep[slot] ? std::optional<double>(log_p[slot]) : std::nullopt);
    const size_t k = input_of[i];
    std::vector<Hypothesis> children =
        branch(std::move(parent), decision, inputs[k], outcomes[k],
               considered ? &(*considered)[k] : nullptr, followed[i].outcomes, child_log_p);
    for (auto& c : children) hyps_.push_back(std::move(c));
  }
  settle();
}

HybridFilter::Followed HybridFilter::follow_outcomes(
    const Hypothesis& parent, const std::vector<tsbi::Outcome>& outcomes) const {
  // Outcomes too improbable to follow get no child; the others share the
  // parent's weight in proportion.
  Followed f;
  f.outcomes = tsbi::probable_outcomes(outcomes, opt_.tsbi.min_probability);
  double followed = 0.0;
  for (size_t k : f.outcomes) followed += outcomes[k].probability;
  const double evidence =
      opt_.hybrid.event_evidence ? tsbi::log_evidence(outcomes, opt_.tsbi.log_eta) : 0.0;
  for (size_t k : f.outcomes)
    f.log_weights.push_back(parent.topo.log_weight +
                            (std::log(outcomes[k].probability / followed) + evidence));
  return f;
}

std::vector<Hypothesis> HybridFilter::branch(Hypothesis parent,
                                             const area::AreaDecision& decision,
                                             const EventInput& input,
                                             const std::vector<tsbi::Outcome>& outcomes,
                                             const std::vector<tsbi::CandidateReport>* considered,
                                             const std::vector<size_t>& follow,
                                             const std::vector<std::optional<double>>& log_p) {
  const AreaId c = parent.current_area();
  const metric_slam::GridRbpf& f = parent.filter;
  const size_t best = f.best_index();
  const metric_slam::Particle& bp = f.particles()[best];
  const std::vector<double> w = f.weights();
  // Steps the particles made since the snapshot (0 when applied at once).
  const bool late = input.step != step_ && input.area_start_step == parent.area_start_step;
  const size_t snapshot_index = static_cast<size_t>(input.step - parent.area_start_step);

  // The new area's keyframes, to seed a fresh map with.
  std::vector<metric_slam::SeedScan> seeds;
  for (const auto& [idx, kf] : keyframes_in_path(decision, parent.area_start_step, bp.path.size()))
    seeds.push_back({idx, kf->scan.get()});

  TransitionEvent ev;
  ev.step = input.step;
  ev.time = input.time;
  ev.hypothesis = parent.id;
  ev.parent_probability = input.probability;
  ev.from_area = c;
  ev.outcomes = outcomes;
  if (considered) ev.considered = *considered;
  if (opt_.hybrid.record_closure_views) {
    ev.observed_points =
        std::make_shared<const std::vector<Point2D>>(input.observations.points.hit);
    for (const tsbi::Outcome& o : outcomes)
      ev.candidate_maps.push_back(o.is_new() ? nullptr : input.map.area(o.area).map);
  }
  const PoseGaussian& robot = input.robot;

  // The area being left is archived under this hypothesis, with the best
  // particle's map and path.
  parent.map.archive_map(c, bp.map);
  auto seg = std::make_shared<TrajectorySegment>();
  seg->area = c;
  seg->first_step = parent.area_start_step;
  seg->poses = bp.estimates;
  seg->blind = f.blind_trace();
  parent.trajectory.push_back(std::move(seg));
  // The snapshot's robot pose in the AAM frame (the known-area outcomes
  // place the robot as it was then).
  const Pose2D aam_then = parent.aam_from_area + robot.mean;

  ev.children.assign(ev.outcomes.size(), kNoChild);
  ev.entered.assign(ev.outcomes.size(), topology::kNoArea);
  // The id a new area gets, read before the parent moves into a child.
  const AreaId next_area = parent.map.next_area_id();
  size_t last_built = follow.size();
  for (size_t fi = 0; fi < follow.size(); ++fi)
    if (log_p[fi]) last_built = fi;
  std::vector<Hypothesis> children;
  for (size_t fi = 0; fi < follow.size(); ++fi) {
    const size_t k = follow[fi];
    const tsbi::Outcome& o = ev.outcomes[k];
    // Every followed outcome takes an id (the random streams derive from
    // it), built or not: the events list the children pruning dropped.
    const uint32_t id = next_hypothesis_id_++;
    ev.children[k] = id;
    if (!log_p[fi]) {
      ev.entered[k] = o.is_new() ? next_area : o.area;
      continue;
    }
    // The last child built takes the parent itself; the others copy it
    // (maps and area tables are shared copy-on-write).
    Hypothesis child = fi == last_built ? std::move(parent) : parent;
    child.id = id;
    child.filter.reseed(mix_seed(opt_.rbpf.seed ^ mix_seed(child.id)));
    child.topo.log_weight = *log_p[fi];
    child.area_start_step = step_;
    AreaId entered;
    if (o.is_new()) {
      const Eigen::Matrix3d blind = child.filter.blind_cov();  // reset by start_new_area
      const std::vector<Pose2D> origins = child.filter.start_new_area(seeds, best);
      PoseGaussian arc(origins[best], spread(origins, w, origins[best]) + blind);
      const double len = origins[best].norm();
      const double sxy = opt_.hybrid.arc_floor_xy(len), sth = opt_.hybrid.arc_floor_theta(len);
      arc.cov.diagonal() += Eigen::Vector3d(sxy * sxy, sxy * sxy, sth * sth);
      entered = child.map.next_area_id();
      topology::ReferenceFrame frame;
      frame.parent = c;
      frame.origin_in_parent = origins[best];
      frame.created_step = step_;
      frame.created_time = time_;
      child.map.add_area(entered, frame);
      child.map.add_arc_measurement(c, entered, arc);
      child.aam_from_area = child.aam_from_area + origins[best];
    } else {
      entered = o.area;
      // Each particle's pose in the known area: a draw from the match
      // posterior (what the observations say, not where the particle was),
      // moved on by the particle's own motion since the snapshot.
      Random rng(mix_seed(opt_.rbpf.seed ^ mix_seed(step_ * 1000003ULL + child.id)));
      auto moved_on = [&](const Pose2D& x, const metric_slam::Particle& p) {
        return late && snapshot_index < p.path.size()
                   ? x + (p.path.back() - p.path[snapshot_index])
                   : x;
      };
      std::vector<Pose2D> poses;
      for (const metric_slam::Particle& p : child.filter.particles())
        poses.push_back(moved_on(topology::sample(o.robot, rng), p));
      // The robot's pose now, as the match put it (moved on as the best
      // particle moved since the snapshot): where the known map does not
      // reach what the robot sees from there, its last scan goes with it.
      const Pose2D now = moved_on(o.robot.mean, child.filter.particles()[best]);
      child.filter.load_area(*child.map.area(o.area).map, poses, &now);
      tlca::ClosureRecord rec;
      rec.from = c;
      rec.to = o.area;
      rec.step = input.step;
      if (const topology::Arc* a = child.map.find_arc(c, o.area)) rec.arc_before = *a;
      // gamma's frame in c's frame: the robot in c composed with the inverse
      // of the robot in gamma (both at the snapshot).
      rec.measurement = topology::compose(robot, topology::inverse(o.robot));
      const double sxy = opt_.hybrid.arc_std_xy, sth = opt_.hybrid.arc_std_theta;
      rec.measurement.cov.diagonal() += Eigen::Vector3d(sxy * sxy, sxy * sxy, sth * sth);
      child.map.add_arc_measurement(c, o.area, rec.measurement);
      child.pending_closures.push_back(rec);
      child.aam_from_area = aam_then + o.robot.mean.inverse();
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
  return normalised_exp(std::move(lw));
}

void HybridFilter::keep_most_probable() {
  if (hyps_.size() < 2) return;
  const size_t b = static_cast<size_t>(&best() - hyps_.data());
  Hypothesis kept = std::move(hyps_[b]);
  hyps_.clear();
  hyps_.push_back(std::move(kept));
  normalise_and_prune();
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

std::vector<char> HybridFilter::survivors(const std::vector<double>& log_weights,
                                          std::vector<double>* log_p) const {
  // Normalised, so the kept weights stay near zero and never lose precision.
  const std::vector<double> p = normalised_exp(log_weights);
  log_p->clear();
  for (double x : p) log_p->push_back(std::log(x));
  std::vector<size_t> order(p.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return p[a] > p[b]; });
  std::vector<char> keep(p.size(), 0);
  for (size_t r = 0; r < order.size(); ++r)
    keep[order[r]] = r == 0 || (p[order[r]] >= opt_.hybrid.prune_probability &&
                                r < static_cast<size_t>(opt_.hybrid.max_hypotheses));
  return keep;
}

void HybridFilter::normalise_and_prune() {
  std::vector<double> lw, log_p;
  for (const auto& h : hyps_) lw.push_back(h.topo.log_weight);
  const std::vector<char> keep = survivors(lw, &log_p);
  std::vector<Hypothesis> kept;
  for (size_t i = 0; i < hyps_.size(); ++i)
    if (keep[i]) {
      hyps_[i].topo.log_weight = log_p[i];
      kept.push_back(std::move(hyps_[i]));
    }
  hyps_ = std::move(kept);
  settle();
}

void HybridFilter::settle() {
  std::sort(hyps_.begin(), hyps_.end(),
            [](const Hypothesis& a, const Hypothesis& b) { return a.id < b.id; });
  const std::vector<double> p = probabilities();
  for (size_t i = 0; i < hyps_.size(); ++i) hyps_[i].topo.log_weight = std::log(p[i]);
  stats_.max_hypotheses_alive = std::max(stats_.max_hypotheses_alive, hyps_.size());
  share_particles(p);
}

void HybridFilter::share_particles(const std::vector<double>& p) {
  // Each hypothesis's share of the particle budget follows its probability:
  // grown at once when it rises, shrunk only when it has halved (resizing
  // costs diversity, so small changes are left alone).
  const int n = opt_.rbpf.particles;
  if (opt_.hybrid.min_particles == 0) return;  // a full set each
  const int floor = std::min(opt_.hybrid.min_particles, n);
  for (size_t i = 0; i < hyps_.size(); ++i) {
    metric_slam::GridRbpf& f = hyps_[i].filter;
    if (f.particles().empty()) continue;
    const size_t target = static_cast<size_t>(
        std::clamp(static_cast<int>(std::lround(n * p[i])), floor, n));
    const size_t now = f.particles().size();
    if (target > now || 2 * target <= now) f.resize(target);
  }
}

void HybridFilter::forget_shared_history() {
  std::vector<topology::TopologicalHypothesis> t;
  for (const auto& h : hyps_) t.push_back(h.topo);
  const std::vector<topology::PathEntry> common = topology::common_prefix(t);
  if (common.size() <= 1) return;
  const size_t n = topology::forget_common_history(t);
  accepted_path_.insert(accepted_path_.end(), common.begin(), common.begin() + n);
  for (size_t i = 0; i < hyps_.size(); ++i) hyps_[i].topo.path = t[i].path;
  stats_.forgotten_path_entries += n;
}

std::optional<AlignmentJob> HybridFilter::accept_if_dominant() {
  const std::vector<double> p = probabilities();
  const auto winner = tlca::dominant(p, opt_.tlca);
  if (!winner) {
    std::optional<AlignmentJob> job = accept_shared_closures(p);
    // Otherwise no acceptance: only the history every hypothesis shares is
    // forgotten.
    forget_shared_history();
    return job;
  }
  Hypothesis& w = hyps_[*winner];
  if (hyps_.size() == 1 && w.pending_closures.empty() && w.topo.path.size() <= 1)
    return std::nullopt;
  AlignmentJob job;
  job.step = step_;
  job.hypothesis = w.id;
  job.probability = p[*winner];
  job.dropped = hyps_.size() - 1;
  job.closures.swap(w.pending_closures);
  job.map = w.map;
  // The accepted path is forgotten up to the current area.
  const size_t n = w.topo.path.size() - 1;
  accepted_path_.insert(accepted_path_.end(), w.topo.path.begin(), w.topo.path.begin() + n);
  w.topo.path.erase(w.topo.path.begin(), w.topo.path.begin() + n);
  stats_.forgotten_path_entries += n;
  w.topo.log_weight = 0.0;
  Hypothesis survivor = std::move(w);
  hyps_.clear();
  hyps_.push_back(std::move(survivor));
  return job;
}

namespace {

// How many of `a`'s first closures are `b`'s first: records copied from a
// common ancestor, so bit for bit the same.
size_t common_prefix(const std::vector<tlca::ClosureRecord>& a,
                     const std::vector<tlca::ClosureRecord>& b) {
  size_t n = 0;
  for (; n < a.size() && n < b.size(); ++n) {
    const tlca::ClosureRecord& x = a[n];
    const tlca::ClosureRecord& y = b[n];
    if (x.from != y.from || x.to != y.to || x.step != y.step ||
        x.measurement.mean.x != y.measurement.mean.x ||
        x.measurement.mean.y != y.measurement.mean.y ||
        x.measurement.mean.theta != y.measurement.mean.theta ||
        x.measurement.cov != y.measurement.cov)
      break;
  }
  return n;
}

}  // namespace

std::optional<AlignmentJob> HybridFilter::accept_shared_closures(const std::vector<double>& p) {
  if (opt_.tlca.policy != tlca::AcceptancePolicy::kProbability || hyps_.size() < 2)
    return std::nullopt;
  size_t best = 0;
  for (size_t i = 1; i < hyps_.size(); ++i)
    if (p[i] > p[best]) best = i;
  const std::vector<tlca::ClosureRecord>& mine = hyps_[best].pending_closures;
  // The longest run of the most probable hypothesis's first closures that
  // hypotheses of accept_probability in all hold.
  std::vector<size_t> common(hyps_.size());
  for (size_t i = 0; i < hyps_.size(); ++i)
    common[i] = common_prefix(hyps_[i].pending_closures, mine);
  std::vector<char> holds(hyps_.size(), 0);
  double mass = 0.0;
  size_t n = mine.size();
  for (; n > 0; --n) {
    mass = 0.0;
    for (size_t i = 0; i < hyps_.size(); ++i) {
      holds[i] = common[i] >= n ? 1 : 0;
      if (holds[i]) mass += p[i];
    }
    if (mass >= opt_.tlca.accept_probability) break;
  }
  if (n == 0) return std::nullopt;
  AlignmentJob job;
  job.step = step_;
  job.hypothesis = hyps_[best].id;
  job.probability = mass;
  job.map = hyps_[best].map;
  job.closures.assign(mine.begin(), mine.begin() + static_cast<std::ptrdiff_t>(n));
  std::vector<Hypothesis> kept;
  for (size_t i = 0; i < hyps_.size(); ++i) {
    if (!holds[i]) {
      ++job.dropped;
      continue;
    }
    Hypothesis& h = hyps_[i];
    h.pending_closures.erase(h.pending_closures.begin(),
                             h.pending_closures.begin() + static_cast<std::ptrdiff_t>(n));
    kept.push_back(std::move(h));
  }
  hyps_ = std::move(kept);
  normalise_and_prune();
  return job;
}

std::vector<tlca::ClosureReport> HybridFilter::align(const AlignmentJob& job) const {
  // Each closure is aligned alone (an acceptance brings up to tens of them).
  std::vector<tlca::ClosureReport> reports(job.closures.size());
  topology_pool_->parallel_for(job.closures.size(), [&](size_t i) {
    reports[i] = tlca::align_closure(job.map, job.closures[i], opt_.tlca);
  });
  return reports;
}

void HybridFilter::apply_alignment(const AlignmentJob& job,
                                   const std::vector<tlca::ClosureReport>& reports) {
  for (const tlca::ClosureReport& r : reports) {
    for (Hypothesis& h : hyps_) tlca::apply_closure(h.map, r);
    ++stats_.loop_closures_accepted;
  }
  if (job.dropped == 0 && reports.empty()) return;
  AcceptanceEvent ev;
  ev.step = job.step;
  ev.hypothesis = job.hypothesis;
  ev.probability = job.probability;
  ev.dropped = job.dropped;
  ev.closures = reports;
  acceptances_.push_back(std::move(ev));
}

size_t HybridFilter::map_memory_bytes() const {
  grid::TileTally tally;
  for (const auto& h : hyps_) {
    for (const auto& p : h.filter.particles()) tally.add(p.map);
    for (AreaId id : h.map.area_ids())
      if (const auto& m = h.map.area(id).map) tally.add(*m);
  }
  return tally.bytes();
}

topology::Session HybridFilter::session(const area::OnlinePartitioner& partitioner) const {
  topology::Session s;
  s.steps = stats_.steps;
  s.time = time_;
  const std::vector<double> p = probabilities();
  for (size_t i = 0; i < hyps_.size(); ++i) {
    const Hypothesis& h = hyps_[i];
    topology::SessionHypothesis sh;
    sh.id = h.id;
    sh.map = h.map;
    sh.map.archive_map(h.current_area(), h.filter.best().map);
    sh.topo = h.topo;
    sh.topo.log_weight = std::log(p[i]);
    sh.robot = h.filter.best().path.back();
    // Saved in the keyframes' frame, which the saved area graph is in.
    sh.aam_from_area = h.keyframes_from_aam + h.aam_from_area;
    sh.pending_closures = h.pending_closures;
    s.hypotheses.push_back(std::move(sh));
  }
  for (int id : partitioner.window()) {
    const KeyframeRecord& kf = keyframes_[static_cast<size_t>(id)];
    s.area_graph.push_back({kf.pose, *kf.scan, kf.step});
  }
  return s;
}

void HybridFilter::resume(const topology::Session& s, area::OnlinePartitioner& partitioner) {
  if (!hyps_.empty() || stats_.steps != 0)
    throw Error(ExitCode::kInternal, "resume() after the first step");
  if (s.hypotheses.empty()) throw InputError("the saved run has no hypotheses");
  stats_.steps = s.steps;
  step_ = s.steps - 1;
  time_ = s.time;
  for (const topology::SessionHypothesis& sh : s.hypotheses) {
    Hypothesis h{metric_slam::GridRbpf(opt_.rbpf, pool_)};
    h.id = sh.id;
    h.filter.reseed(mix_seed(opt_.rbpf.seed ^ mix_seed(h.id) ^ mix_seed(s.steps)));
    h.map = sh.map;
    h.topo = sh.topo;
    // The particles' paths start at the saved run's last step.
    h.area_start_step = s.steps - 1;
    h.aam_from_area = sh.aam_from_area;
    // Closures TSBI made before the save are fine-aligned when this
    // hypothesis is accepted, as in an uninterrupted run.
    h.pending_closures = sh.pending_closures;
    h.filter.restart(*h.map.area(h.current_area()).map, sh.robot);
    next_hypothesis_id_ = std::max(next_hypothesis_id_, h.id + 1);
    hyps_.push_back(std::move(h));
  }
  normalise_and_prune();
  // The area abstraction's graph as it was saved. Started empty, it would
  // see only the keyframes after the resume, and the current area would be
  // cut tens of steps later than in the uninterrupted run (the Malaga log's
  // fourth area at step 175 instead of 163): every later new-area event,
  // the ones that close loops included, would come late or not at all.
  // These keyframes precede the particles' paths (step 0 < the first step
  // of every path), so, like an earlier area visit's, they seed no map and
  // pose no observation.
  for (const topology::Keyframe& kf : s.area_graph) {
    partitioner.add_keyframe(area::Keyframe{area::PoseGaussian(kf.pose), kf.scan});
    keyframes_.push_back({0, std::make_shared<const LaserScan>(kf.scan), kf.pose});
    has_keyframe_ = true;
    last_keyframe_pose_ = kf.pose;
  }
}

topology::HmtMap HybridFilter::final_map(
    std::vector<tlca::ClosureReport>* pending_reports) const {
  const Hypothesis& h = best();
  topology::HmtMap m = h.map;
  m.archive_map(h.current_area(), h.filter.best().map);
  // As an acceptance does (align, then apply): every closure aligned on the
  // same snapshot, fused in order.
  AlignmentJob job;
  job.closures = h.pending_closures;
  job.map = m;
  const std::vector<tlca::ClosureReport> reports = align(job);
  for (const tlca::ClosureReport& r : reports) tlca::apply_closure(m, r);
  if (pending_reports) *pending_reports = reports;
  return m;
}

std::vector<TrajectorySegment> HybridFilter::final_trajectory() const {
  const Hypothesis& h = best();
  std::vector<TrajectorySegment> out;
  for (const auto& s : h.trajectory) out.push_back(*s);
  TrajectorySegment cur;
  cur.area = h.current_area();
  cur.first_step = h.area_start_step;
  cur.poses = h.filter.best().estimates;
  cur.blind = h.filter.blind_trace();
  out.push_back(std::move(cur));
  return out;
}

}  // namespace hmt::hybrid

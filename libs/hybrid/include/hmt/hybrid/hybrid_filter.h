// The HMT-SLAM estimator (002 Sec. III-V) run step by step: a particle
// filter over the robot's hybrid path whose particles are grouped by
// topological hypothesis (hypothesis.h).
//
// Each step:
//  1. Metric SLAM: every hypothesis's particles process the odometry and the
//     scan in the current area's map; the hypothesis's log weight gains the
//     step's evidence.
//  2. Area abstraction (AAM): every keyframe_distance / keyframe_angle of
//     motion of the most probable hypothesis's best particle, the scan joins
//     the keyframe graph (area::OnlinePartitioner); a good enough normalized
//     cut says the robot entered a new area. Each hypothesis's current area
//     stores the keyframe too, unless it holds one within that spacing.
//  3. Topological inference (TSBI), on a new-area event, once per
//     hypothesis: the transition model (tsbi::TransitionModel) gives eta for
//     an unexplored area and F(gamma) for each known area; every outcome
//     above the threshold becomes a child hypothesis with weight parent x
//     probability. "New area": the particles start a fresh map (seeded with
//     the new area's keyframes) and the arc from the area left is measured
//     from the particles' origins. "Known area gamma": the particles load
//     gamma's stored map at poses drawn from the match posterior; the arc
//     to gamma gets that measurement.
//  4. Hypotheses under prune_probability are dropped; at most max_hypotheses
//     are kept. At an event this is decided on the children's weights
//     before they are built, so a child pruning drops is never built.
//  5. Loop-closure acceptance (TLCA): when one hypothesis dominates (policy
//     in tlca::TlcaOptions) the others are dropped, its loop closures are
//     fine-aligned and fused into the arcs, and the shared topological
//     history is forgotten. Short of that, the closures that hypotheses of
//     accept_probability in all share are accepted alone.
//
// process() runs the five steps in order. The same steps are also offered one
// by one (metric_step, prepare_event / evaluate / apply_event,
// accept_if_dominant / align / apply_alignment) so the framework can run the
// area abstraction, TSBI and TLCA on threads of their own: evaluate() and
// align() are const and read only the snapshot they are given, and the
// apply_ methods accept results computed some steps earlier (live mode).
//
// Deterministic: hypotheses are processed in id order, each with its own
// random streams derived from (seed, hypothesis id); particle work is
// parallel but index-deterministic (WorkerPool). Not
// synchronised: one thread drives the non-const methods; evaluate() and
// align() may run on other threads meanwhile.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "hmt/area/online_partitioner.h"
#include "hmt/hybrid/hybrid_options.h"
#include "hmt/hybrid/hypothesis.h"
#include "hmt/topology/topology_file.h"
#include "hmt/tsbi/transition_model.h"

namespace hmt::checkpoint {
struct Access;  // hmt/checkpoint/checkpoint.h
}  // namespace hmt::checkpoint

namespace hmt::hybrid {

constexpr uint32_t kNoChild = 0xffffffffu;

// One TSBI evaluation: a hypothesis at a new-area event and what became of it.
struct TransitionEvent {
  uint64_t step = 0;
  double time = 0.0;
  uint32_t hypothesis = 0;  // the parent
  double parent_probability = 0.0;
  topology::AreaId from_area = topology::kNoArea;
  std::vector<tsbi::Outcome> outcomes;   // every outcome weighed
  // Every known area the arcs reached, and what TSBI made of it (empty if
  // the event's evaluation was not asked for them).
  std::vector<tsbi::CandidateReport> considered;
  // Per outcome: the child hypothesis and the area it entered (kNoChild and
  // kNoArea for outcomes too improbable to follow).
  std::vector<uint32_t> children;
  std::vector<topology::AreaId> entered;
  // With HybridOptions::record_closure_views only (else empty): the
  // observations' end points in the robot frame at the snapshot (what
  // F(gamma) was computed on; Outcome::prior and Outcome::robot place them in
  // a known area), and per outcome the known area's grid as TSBI saw it
  // (null for the new area).
  std::shared_ptr<const std::vector<Point2D>> observed_points;
  std::vector<std::shared_ptr<const grid::OccupancyGrid>> candidate_maps;
};

// One acceptance by TLCA.
struct AcceptanceEvent {
  uint64_t step = 0;
  uint32_t hypothesis = 0;
  double probability = 0.0;
  size_t dropped = 0;  // hypotheses dropped by this acceptance
  std::vector<tlca::ClosureReport> closures;
};

// TSBI's input for one hypothesis at a new-area event: a snapshot taken by
// prepare_event (the map is shared copy-on-write), so evaluate() can run on
// another thread while the particles move on.
struct EventInput {
  uint32_t hypothesis = 0;
  uint64_t step = 0;  // the step at which the snapshot was taken
  double time = 0.0;
  double probability = 0.0;  // the hypothesis's, at the snapshot
  topology::AreaId from_area = topology::kNoArea;
  uint64_t area_start_step = 0;
  topology::HmtMap map;
  topology::PoseGaussian robot;  // in from_area: best particle, particles' spread
  tsbi::Observations observations;
  // The keyframe scans observations.scans point to.
  std::vector<std::shared_ptr<const LaserScan>> scans;
};

// What TLCA must do after an acceptance: fine-align the accepted
// hypothesis's loop closures over a snapshot of its map.
struct AlignmentJob {
  uint64_t step = 0;
  uint32_t hypothesis = 0;
  double probability = 0.0;
  size_t dropped = 0;
  topology::HmtMap map;
  std::vector<tlca::ClosureRecord> closures;
};

struct HybridStats {
  size_t steps = 0;
  size_t keyframes = 0;
  size_t new_area_events = 0;
  size_t loop_closures_accepted = 0;
  size_t max_hypotheses_alive = 1;
  size_t forgotten_path_entries = 0;
};

class HybridFilter {
  // Checkpoints save and restore every member, bit for bit.
  friend struct hmt::checkpoint::Access;

 public:
  explicit HybridFilter(const HmtOptions& options);

  // All five steps, in order (the sequential pipeline).
  void process(const LogStep& step);
  // After the last step (the sequential pipeline): the area the log ends in
  // is put to TSBI once more (OnlinePartitioner::end_of_log), unless an area
  // event was applied at the last step, and a hypothesis that then
  // dominates is accepted.
  void finish();
  // Drops every hypothesis but the most probable one. Before the end-of-log
  // event: its outcomes split their parent's probability, and where two
  // overlapping areas both hold the place the log ends in, the split would
  // rank the topology below a rival for an ambiguity of its own layout,
  // not for explaining the data worse; with the log over, no later scan
  // can weigh them again. So the event decides within the topology the
  // whole log made most probable.
  void keep_most_probable();

  // Step 1, metric SLAM: every hypothesis processes the step; returns the
  // keyframe (in the area abstraction's continuous frame) when one is due.
  // Keyframes are numbered from 0 in the order returned, as the AAM does.
  std::optional<area::Keyframe> metric_step(const LogStep& step);
  // Step 3, TSBI: snapshots of every hypothesis at a new-area decision,
  // their evaluation (const, thread-safe) and the branching by the results
  // (outcomes[i] for inputs[i]). Inputs of hypotheses gone in the meantime
  // are ignored; a result older than the current step is carried forward
  // by each particle's own motion since the snapshot.
  std::vector<EventInput> prepare_event(const area::AreaDecision& decision) const;
  // The outcomes of every input of one event (out[i] for inputs[i]),
  // weighed together (tsbi::TransitionModel::evaluate_all). `considered`,
  // if given: what TSBI made of every known area, recorded in the event by
  // apply_event (considered[i] for inputs[i]).
  std::vector<std::vector<tsbi::Outcome>> evaluate(
      const std::vector<EventInput>& inputs,
      std::vector<std::vector<tsbi::CandidateReport>>* considered = nullptr) const;
  void apply_event(const area::AreaDecision& decision, const std::vector<EventInput>& inputs,
                   const std::vector<std::vector<tsbi::Outcome>>& outcomes,
                   const std::vector<std::vector<tsbi::CandidateReport>>* considered = nullptr);
  // Step 5, TLCA: when a hypothesis dominates, the others are dropped and
  // the shared history forgotten at once; the job says which closures to
  // fine-align (align() is const and thread-safe), apply_alignment fuses
  // them into the arcs of every surviving hypothesis (all descend from the
  // accepted one).
  std::optional<AlignmentJob> accept_if_dominant();
  // Frees the scans of the keyframes before `id` (an AreaDecision's
  // oldest_in_window, or older): the area abstraction will not name them
  // again, and a long run would otherwise hold every keyframe's scan.
  void release_keyframe_scans_before(int id);
  std::vector<tlca::ClosureReport> align(const AlignmentJob& job) const;
  void apply_alignment(const AlignmentJob& job, const std::vector<tlca::ClosureReport>& reports);

  uint64_t steps_processed() const { return stats_.steps; }

  // The state to continue from (hmt_map.bin): every hypothesis's map with
  // its current area archived from its best particle, its path and log
  // probability, and where its best particle is.
  // `partitioner`: the area abstraction that ran beside this filter (its
  // graph is saved too); process() uses the filter's own.
  topology::Session session(const area::OnlinePartitioner& partitioner) const;
  topology::Session session() const { return session(aam_); }
  // Continues a saved run; call before the first step. Each hypothesis's
  // particles restart at its saved robot pose in its current area's map;
  // steps are numbered on from the saved run's; the area abstraction's
  // graph is the saved one (the same keyframes, so the same weights);
  // closures not yet accepted when the run was
  // saved are fine-aligned when their hypothesis is accepted, as they would
  // have been without the stop.
  void resume(const topology::Session& session, area::OnlinePartitioner& partitioner);
  void resume(const topology::Session& session) { resume(session, aam_); }

  const std::vector<Hypothesis>& hypotheses() const { return hyps_; }
  // Normalised probabilities, in the order of hypotheses().
  std::vector<double> probabilities() const;
  // The most probable hypothesis (lowest id on ties).
  const Hypothesis& best() const;
  // Eq. 14: probability of each current area.
  std::map<topology::AreaId, double> position_pmf() const;

  const std::vector<TransitionEvent>& transitions() const { return transitions_; }
  const std::vector<AcceptanceEvent>& acceptances() const { return acceptances_; }
  const HybridStats& stats() const { return stats_; }
  // Keyframe scans still held for the area abstraction.
  size_t keyframe_scans_held() const;
  // The topological path accepted and forgotten by TLCA (oldest first);
  // followed by the surviving hypotheses' own paths.
  const std::vector<topology::PathEntry>& accepted_path() const { return accepted_path_; }

  // Bytes of the distinct grid tiles held by all particles of all hypotheses
  // and by the archived area maps.
  size_t map_memory_bytes() const;

  // The most probable hypothesis's HMT map, its current area's map archived
  // from its best particle, and its loop closures not yet accepted (the log
  // ended before the hypothesis dominated) fine-aligned, checked and fused
  // as TLCA would at acceptance: this map is the one the run outputs, and a
  // closure left with TSBI's coarse measurement would place the areas it
  // joins decimetres off. Their reports go to `pending_reports` if given.
  // The filter itself is unchanged (its session keeps every hypothesis).
  topology::HmtMap final_map(std::vector<tlca::ClosureReport>* pending_reports = nullptr) const;
  // Its best particle's trajectory: the finished area visits and the current
  // one, in log order (one pose per step, each in its area's frame).
  std::vector<TrajectorySegment> final_trajectory() const;

 private:
  // The sequential pipeline's steps 3 and 5: a new-area decision put to
  // TSBI and applied; a dominant hypothesis accepted and its closures fused.
  void run_event(const area::AreaDecision& decision);
  void accept_and_align();

  struct KeyframeRecord {
    uint64_t step = 0;
    // Shared, so a snapshot (EventInput) keeps the scans it points to
    // alive and in place while this table grows; null once released
    // (release_keyframe_scans_before).
    std::shared_ptr<const LaserScan> scan;
    Pose2D pose;  // in the AAM frame, as the partitioner has it
  };
  void start(const LogStep& step);
  std::optional<area::Keyframe> keyframe_due(const LogStep& step);
  // The new area's keyframes that a path begun at `area_start_step`, of
  // `path_size` poses, holds (earlier ones are in no path), each with its
  // index in that path.
  std::vector<std::pair<size_t, const KeyframeRecord*>> keyframes_in_path(
      const area::AreaDecision& decision, uint64_t area_start_step, size_t path_size) const;
  // The outcomes of an event a hypothesis follows, and the log weight of
  // the child each would get.
  struct Followed {
    std::vector<size_t> outcomes;  // indices into the event's outcomes
    std::vector<double> log_weights;
  };
  Followed follow_outcomes(const Hypothesis& parent,
                           const std::vector<tsbi::Outcome>& outcomes) const;
  // The children of `parent` for the followed outcomes `follow`: those with
  // a log probability in `log_p` (the ones pruning keeps) are built with it.
  // The event is recorded with its outcomes and, if given, `considered`.
  std::vector<Hypothesis> branch(Hypothesis parent, const area::AreaDecision& decision,
                                 const EventInput& input,
                                 const std::vector<tsbi::Outcome>& outcomes,
                                 const std::vector<tsbi::CandidateReport>* considered,
                                 const std::vector<size_t>& follow,
                                 const std::vector<std::optional<double>>& log_p);
  // Which hypotheses of these log weights pruning keeps (the most probable
  // always; the others at least prune_probability and among the
  // max_hypotheses most probable), and each one's log probability among
  // them all.
  std::vector<char> survivors(const std::vector<double>& log_weights,
                              std::vector<double>* log_p) const;
  void normalise_and_prune();
  // After pruning: id order, the weights normalised over what is left, the
  // particles shared out.
  void settle();
  void share_particles(const std::vector<double>& probabilities);
  void forget_shared_history();
  // When no hypothesis dominates but the closures the most probable one
  // made first are shared by hypotheses of accept_probability in all (they
  // descend from the hypothesis that made them): those closures are
  // accepted, the hypotheses without them dropped.
  std::optional<AlignmentJob> accept_shared_closures(const std::vector<double>& p);

  HmtOptions opt_;
  std::shared_ptr<WorkerPool> pool_;  // metric SLAM's particles
  // TSBI's candidates and TLCA's closures: a pool of its own, since in live
  // mode those run beside metric SLAM, which must not wait for them. TSBI
  // and TLCA take turns on it.
  std::shared_ptr<WorkerPool> topology_pool_;
  area::OnlinePartitioner aam_;
  // Mutable: its cache of the areas' match fields is used and updated by
  // evaluate() alone (on the TSBI thread, in the framework).
  mutable tsbi::TransitionModel tsbi_;
  std::vector<Hypothesis> hyps_;  // ascending id
  uint32_t next_hypothesis_id_ = 0;
  std::vector<KeyframeRecord> keyframes_;  // by AAM keyframe id
  bool has_keyframe_ = false;
  Pose2D last_keyframe_pose_;  // in the AAM frame
  uint64_t step_ = 0;          // index of the step being processed
  double time_ = 0.0;          // its timestamp
  std::vector<TransitionEvent> transitions_;
  std::vector<AcceptanceEvent> acceptances_;
  std::vector<topology::PathEntry> accepted_path_;
  HybridStats stats_;
};

}  // namespace hmt::hybrid

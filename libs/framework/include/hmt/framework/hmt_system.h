// HMT-SLAM as five concurrent processes over three data layers (002 Sec. V,
// Fig. 8):
//
//   process          thread  reads -> writes                                trigger
//   metric SLAM      yes     log steps -> hybrid filter (particles, hypotheses),
//                            MetricLayer, TopologicalLayer; keyframes to AAM  every step
//   area abstraction yes     keyframes -> partitioner, AreaLayer; decisions     every keyframe
//   TSBI             yes     snapshots of the hypotheses -> transition outcomes every new area
//   TLCA             yes     snapshot of the accepted map -> aligned closures   every acceptance
//   RTL              yes     MetricLayer + queued odometry -> pose now          on request
//
// The hybrid filter is owned by the metric SLAM process: TSBI and TLCA work
// on snapshots it sends them (hybrid::EventInput, hybrid::AlignmentJob) and
// send back results that metric SLAM applies, so no two threads ever write
// the same data. The layers (layers.h) publish what others read.
//
// Modes (framework_options.h): deterministic hand-shakes at every keyframe,
// new area and acceptance, and then equals the sequential
// hybrid::HybridFilter::process() step for step; live never makes metric
// SLAM wait for the other processes.
//
// Life cycle: construct, start(), feed() every step, finish() (drains every
// queue, applies what is outstanding, joins). A process that fails stops
// the pipeline; feed() and finish() rethrow its error. The destructor joins.
#pragma once

#include <cstdint>
#include <functional>
#include <future>
#include <map>
#include <optional>
#include <vector>

#include "hmt/area/online_partitioner.h"
#include "hmt/common/resources.h"
#include "hmt/framework/bounded_queue.h"
#include "hmt/framework/framework_options.h"
#include "hmt/framework/layers.h"
#include "hmt/framework/process.h"
#include "hmt/framework/rtl.h"
#include "hmt/hybrid/hybrid_filter.h"

namespace hmt::checkpoint {
struct Access;  // hmt/checkpoint/checkpoint.h
}  // namespace hmt::checkpoint

namespace hmt::framework {

// What metric SLAM records after each step, for the outputs.
struct HypothesisTrace {
  uint32_t id = 0;
  double probability = 0.0;
  topology::AreaId area = topology::kNoArea;
  double ess = 0.0;
  size_t particles = 0;
};

struct StepTrace {
  uint64_t step = 0;
  double time = 0.0;
  std::map<topology::AreaId, double> pmf;  // 002 Eq. 14
  std::vector<HypothesisTrace> hypotheses;
  size_t areas = 0;  // in the most probable hypothesis's map
  // Sampled every memory_every steps and at the end (0 = not sampled).
  size_t map_memory_bytes = 0;
  size_t peak_rss_bytes = 0;
};

// Milliseconds each process spent on the work of each step (the step that
// triggered it): metric SLAM's own work, without its waits on the others.
struct ProcessTimes {
  std::vector<double> metric_slam, aam, tsbi, tlca;  // indexed by step
};

class HmtSystem {
  // Checkpoints save and restore every member, bit for bit.
  friend struct hmt::checkpoint::Access;

 public:
  HmtSystem(const hybrid::HmtOptions& options, const FrameworkOptions& framework,
            size_t memory_every = 50);
  ~HmtSystem();
  HmtSystem(const HmtSystem&) = delete;
  HmtSystem& operator=(const HmtSystem&) = delete;

  // Continues a saved run (hybrid::HybridFilter::resume); before start().
  // Steps are then numbered on from the saved run's.
  void resume(const topology::Session& session);
  void start();
  // Hands one log step to RTL (its odometry) and to metric SLAM (waits while
  // its inbox is full). Steps are numbered in feeding order, from 0 (or from
  // the saved run's count after resume()).
  void feed(const LogStep& step);
  // No more steps: waits for every process to finish its work, applies the
  // outstanding results, joins the threads. Rethrows a process's failure.
  void finish();
  // Runs `task` on the metric SLAM thread once every step fed so far has
  // been processed, and waits for it; rethrows its error (or the pipeline's,
  // if it stopped first). In deterministic mode the other processes are then
  // idle, every answer applied: the one consistent state a checkpoint can
  // save (hmt/checkpoint/checkpoint.h). Between start() and finish().
  void run_between_steps(const std::function<void()>& task);

  // RTL: the robot's pose now; answered by the RTL thread at any time after
  // start(), whatever metric SLAM is doing.
  std::future<RtlPose> locate() { return rtl_.request(); }

  // Read by any thread at any time.
  const MetricLayer& metric_layer() const { return metric_layer_; }
  const AreaLayer& area_layer() const { return area_layer_; }
  const TopologicalLayer& topological_layer() const { return topo_layer_; }
  uint64_t steps_fed() const { return fed_; }

  // After finish() only.
  const hybrid::HybridFilter& filter() const { return filter_; }
  // The state to continue from (hmt_map.bin), with the area abstraction's
  // graph; after finish().
  topology::Session session() const { return filter_.session(partitioner_); }
  const std::vector<StepTrace>& traces() const { return traces_; }
  const ProcessTimes& times() const { return times_; }

  // Called by the metric SLAM thread as each step starts (tests use it to
  // hold a step while they query RTL). Set before start().
  void set_step_hook(std::function<void(uint64_t)> hook) { step_hook_ = std::move(hook); }
  // Called by the TSBI thread before each evaluation, with the step of its
  // snapshot (tests use it to hold TSBI). Set before start().
  void set_event_hook(std::function<void(uint64_t)> hook) { event_hook_ = std::move(hook); }

 private:
  struct StepMsg {
    bool drain = false;
    std::function<void()> task;  // run_between_steps(): no step
    uint64_t index = 0;
    LogStep step;
  };
  struct KeyframeMsg {
    uint64_t step = 0;
    area::Keyframe keyframe;
    // No keyframe: the log is over (OnlinePartitioner::end_of_log).
    bool end_of_log = false;
  };
  struct DecisionMsg {
    uint64_t step = 0;
    area::AreaDecision decision;
  };
  struct EventMsg {
    uint64_t step = 0;
    area::AreaDecision decision;
    std::vector<hybrid::EventInput> inputs;
    std::vector<std::vector<tsbi::Outcome>> outcomes;  // filled by TSBI
    std::vector<std::vector<tsbi::CandidateReport>> considered;  // likewise
  };
  struct AlignmentMsg {
    hybrid::AlignmentJob job;
    std::vector<tlca::ClosureReport> reports;  // filled by TLCA
  };

  // Metric SLAM thread.
  void on_step(StepMsg& m);
  void on_decision(const DecisionMsg& d);
  void dispatch_event(const area::AreaDecision& decision);
  void on_event_result(const EventMsg& r);
  // TLCA: settles a dominant hypothesis and sends its closures to align
  // (waiting for them in deterministic mode).
  void accept_if_dominant();
  void on_alignment_result(const AlignmentMsg& r);
  void poll_replies();
  void drain();
  uint64_t current_step() const { return filter_.steps_processed() - 1; }
  template <class T>
  T wait_reply(BoundedQueue<T>& q, const char* process);
  void record_step(uint64_t index, double time, bool sample_memory);
  // Other threads.
  void on_keyframe(KeyframeMsg& m);
  void on_event(EventMsg& m);
  void on_alignment(AlignmentMsg& m);
  // Any thread: stops the pipeline after a failure.
  void fail();
  // Rethrows the first failure of a process, if any.
  void rethrow_failure() const;

  const hybrid::HmtOptions options_;
  const FrameworkOptions framework_;
  const size_t memory_every_;
  std::function<void(uint64_t)> step_hook_, event_hook_;

  MetricLayer metric_layer_;
  AreaLayer area_layer_;
  TopologicalLayer topo_layer_;

  // Owned by the metric SLAM thread (between start() and finish()).
  hybrid::HybridFilter filter_;
  size_t aam_outstanding_ = 0;      // keyframes sent, decisions not yet handled
  bool event_in_flight_ = false;    // a TSBI evaluation is out
  MemoryTrimmer trimmer_;           // returns freed pages after events
  int in_flight_oldest_keyframe_ = 0;  // of that evaluation's decision
  uint64_t event_applied_step_ = UINT64_MAX;  // the step of the last area change
  std::vector<area::AreaDecision> waiting_decisions_;  // live: the latest one behind it
  size_t alignments_outstanding_ = 0;
  double waited_ms_ = 0.0;          // this step's waits on other processes
  std::vector<StepTrace> traces_;
  // Each written by its own process's thread only.
  ProcessTimes times_;
  // Owned by the area abstraction thread.
  area::OnlinePartitioner partitioner_;
  // Owned by the feeding thread.
  uint64_t fed_ = 0;

  // Answers back to metric SLAM (capacity: inbox + 2, so a process never
  // waits on a full answer queue while metric SLAM waits on its inbox).
  BoundedQueue<DecisionMsg> decisions_;
  BoundedQueue<EventMsg> event_results_;
  BoundedQueue<AlignmentMsg> alignment_results_;

  // Last: destroyed (joined) first, before the state they use.
  RealTimeLocalizer rtl_;
  Process<KeyframeMsg> aam_;
  Process<EventMsg> tsbi_;
  Process<AlignmentMsg> tlca_;
  Process<StepMsg> metric_;
  bool started_ = false, finished_ = false;
};

}  // namespace hmt::framework

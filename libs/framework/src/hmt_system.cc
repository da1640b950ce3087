#include "hmt/framework/hmt_system.h"

#include <algorithm>
#include <chrono>
#include <future>
#include <memory>
#include <utility>

#include "hmt/common/error.h"
#include "hmt/common/resources.h"

namespace hmt::framework {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

void add_time(std::vector<double>& table, uint64_t step, double ms) {
  if (table.size() <= step) table.resize(step + 1, 0.0);
  table[step] += ms;
}

}  // namespace

HmtSystem::HmtSystem(const hybrid::HmtOptions& options, const FrameworkOptions& framework,
                     size_t memory_every)
    : options_(options),
      framework_(framework),
      memory_every_(memory_every < 1 ? 1 : memory_every),
      filter_(options),
      partitioner_(options.area),
      decisions_(framework.inbox_capacity + 2),
      event_results_(framework.inbox_capacity + 2),
      alignment_results_(framework.inbox_capacity + 2),
      rtl_(metric_layer_, framework.inbox_capacity),
      aam_("area abstraction", framework.inbox_capacity, [this](KeyframeMsg& m) { on_keyframe(m); },
           [this] { fail(); }),
      tsbi_("topological inference", framework.inbox_capacity, [this](EventMsg& m) { on_event(m); },
            [this] { fail(); }),
      tlca_("loop-closure acceptance", framework.inbox_capacity,
            [this](AlignmentMsg& m) { on_alignment(m); }, [this] { fail(); }),
      metric_("metric SLAM", framework.inbox_capacity, [this](StepMsg& m) { on_step(m); },
              [this] { fail(); }) {}

HmtSystem::~HmtSystem() {
  // Not finished (an exception on the caller's side): stop without waiting
  // for the remaining work.
  if (started_ && !finished_) fail();
  metric_.stop();
  tlca_.stop();
  tsbi_.stop();
  aam_.stop();
  rtl_.stop();
}

void HmtSystem::resume(const topology::Session& session) {
  if (started_) throw Error(ExitCode::kInternal, "HmtSystem::resume after start()");
  filter_.resume(session, partitioner_);
  fed_ = session.steps;
}

void HmtSystem::start() {
  if (started_) return;
  started_ = true;
  rtl_.start();
  aam_.start();
  tsbi_.start();
  tlca_.start();
  metric_.start();
}

void HmtSystem::feed(const LogStep& step) {
  if (!started_ || finished_)
    throw Error(ExitCode::kInternal, "HmtSystem::feed outside start()..finish()");
  const uint64_t index = fed_++;
  if (step.has_odometry) rtl_.odometry(index, step.odometry_increment);
  StepMsg m;
  m.index = index;
  m.step = step;
  if (!metric_.post(std::move(m))) {
    rethrow_failure();
    throw Error(ExitCode::kInternal, "the HMT-SLAM pipeline stopped unexpectedly");
  }
}

void HmtSystem::finish() {
  if (finished_) return;
  StepMsg drain;
  drain.drain = true;
  metric_.post(std::move(drain));
  metric_.stop();
  finished_ = true;
  // Metric SLAM has collected every answer: the others are idle.
  tlca_.stop();
  tsbi_.stop();
  aam_.stop();
  rtl_.stop();
  rethrow_failure();
}

void HmtSystem::run_between_steps(const std::function<void()>& task) {
  if (!started_ || finished_)
    throw Error(ExitCode::kInternal, "HmtSystem::run_between_steps outside start()..finish()");
  // The promise travels with the message: if the pipeline stops and drops
  // it, the future reports a broken promise instead of waiting for ever.
  auto done = std::make_shared<std::promise<void>>();
  std::future<void> result = done->get_future();
  StepMsg m;
  m.task = [&task, done] {
    try {
      task();
      done->set_value();
    } catch (...) {
      done->set_exception(std::current_exception());
    }
  };
  if (!metric_.post(std::move(m))) {
    rethrow_failure();
    throw Error(ExitCode::kInternal, "the HMT-SLAM pipeline stopped unexpectedly");
  }
  try {
    result.get();
  } catch (const std::future_error&) {
    rethrow_failure();
    throw Error(ExitCode::kInternal, "the HMT-SLAM pipeline stopped unexpectedly");
  }
}

void HmtSystem::fail() {
  decisions_.close();
  event_results_.close();
  alignment_results_.close();
  // Closing the inboxes wakes a feeder waiting on a full one; the threads
  // drop what is queued and stop after their current message.
  aam_.abort();
  tsbi_.abort();
  tlca_.abort();
  metric_.abort();
}

void HmtSystem::rethrow_failure() const {
  // The first cause: the helpers' errors before metric SLAM's (which only
  // says a helper stopped answering).
  for (const std::exception_ptr& e : {aam_.error(), tsbi_.error(), tlca_.error(), metric_.error()})
    if (e) std::rethrow_exception(e);
}

// ------------------------------------------------------------ metric SLAM

void HmtSystem::on_step(StepMsg& m) {
  if (m.drain) {
    drain();
    return;
  }
  if (m.task) {
    m.task();
    return;
  }
  const Clock::time_point t0 = Clock::now();
  waited_ms_ = 0.0;
  metric_layer_.begin_step(m.index);
  if (step_hook_) step_hook_(m.index);
  if (const std::optional<area::Keyframe> kf = filter_.metric_step(m.step)) {
    ++aam_outstanding_;
    if (!aam_.post({m.index, *kf})) throw Error(ExitCode::kInternal, "area abstraction stopped");
    if (framework_.mode == Mode::kDeterministic) on_decision(wait_reply(decisions_, "area abstraction"));
  }
  if (framework_.mode == Mode::kLive) poll_replies();
  accept_if_dominant();
  record_step(m.index, m.step.timestamp, m.index % memory_every_ == 0);
  add_time(times_.metric_slam, m.index, ms_since(t0) - waited_ms_);
}

template <class T>
T HmtSystem::wait_reply(BoundedQueue<T>& q, const char* process) {
  const Clock::time_point t0 = Clock::now();
  std::optional<T> r = q.pop();
  waited_ms_ += ms_since(t0);
  if (!r) throw Error(ExitCode::kInternal, std::string("the ") + process + " process stopped");
  return std::move(*r);
}

void HmtSystem::poll_replies() {
  while (std::optional<DecisionMsg> d = decisions_.try_pop()) on_decision(*d);
  // One area change per step at most: a second result waits for the next.
  if (event_in_flight_ && event_applied_step_ != current_step())
    if (std::optional<EventMsg> r = event_results_.try_pop()) on_event_result(*r);
  while (std::optional<AlignmentMsg> r = alignment_results_.try_pop()) on_alignment_result(*r);
}

void HmtSystem::on_decision(const DecisionMsg& d) {
  --aam_outstanding_;
  if (d.decision.new_area) {
    // One evaluation at a time: the next needs the hypotheses this one
    // makes. Behind it waits only the latest decision: the robot has
    // crossed the areas of the earlier ones already, and entering each at
    // consecutive steps would only make areas of a step or two.
    if (event_in_flight_)
      waiting_decisions_.assign(1, d.decision);
    else
      dispatch_event(d.decision);
  }
  // The scans older than the area abstraction's window go, except those
  // of the decisions still to be applied (apply_event seeds new areas with
  // them).
  int keep = d.decision.oldest_in_window;
  if (event_in_flight_) keep = std::min(keep, in_flight_oldest_keyframe_);
  for (const area::AreaDecision& w : waiting_decisions_)
    if (!w.new_area_keyframes.empty()) keep = std::min(keep, w.new_area_keyframes.front());
  filter_.release_keyframe_scans_before(keep);
}

void HmtSystem::dispatch_event(const area::AreaDecision& decision) {
  EventMsg e;
  e.step = current_step();
  e.decision = decision;
  e.inputs = filter_.prepare_event(decision);
  event_in_flight_ = true;
  in_flight_oldest_keyframe_ =
      decision.new_area_keyframes.empty() ? 0 : decision.new_area_keyframes.front();
  if (!tsbi_.post(std::move(e))) throw Error(ExitCode::kInternal, "topological inference stopped");
  if (framework_.mode == Mode::kDeterministic)
    on_event_result(wait_reply(event_results_, "topological inference"));
}

void HmtSystem::on_event_result(const EventMsg& r) {
  filter_.apply_event(r.decision, r.inputs, r.outcomes, &r.considered);
  // The event's transients (the parent's copies, the pruned hypotheses'
  // maps) are freed now: their pages go back to the system, every 250
  // steps at most (resources.h).
  trimmer_.maybe_release(current_step());
  event_in_flight_ = false;
  event_applied_step_ = current_step();
  if (!waiting_decisions_.empty()) {
    const area::AreaDecision next = waiting_decisions_.front();
    waiting_decisions_.erase(waiting_decisions_.begin());
    dispatch_event(next);
  }
}

void HmtSystem::accept_if_dominant() {
  std::optional<hybrid::AlignmentJob> job = filter_.accept_if_dominant();
  if (!job) return;
  ++alignments_outstanding_;
  if (!tlca_.post({std::move(*job), {}}))
    throw Error(ExitCode::kInternal, "loop-closure acceptance stopped");
  if (framework_.mode == Mode::kDeterministic)
    on_alignment_result(wait_reply(alignment_results_, "loop-closure acceptance"));
}

void HmtSystem::on_alignment_result(const AlignmentMsg& r) {
  --alignments_outstanding_;
  filter_.apply_alignment(r.job, r.reports);
}

void HmtSystem::drain() {
  // After the last step: every answer still out is awaited and applied, in
  // the order the processes were asked.
  while (aam_outstanding_ > 0) on_decision(wait_reply(decisions_, "area abstraction"));
  while (event_in_flight_) {
    const EventMsg r = wait_reply(event_results_, "topological inference");
    if (event_applied_step_ != current_step()) {
      on_event_result(r);
      continue;
    }
    // The robot already changed area at the last step and the log is over:
    // there is no step left to enter another area at.
    event_in_flight_ = false;
    waiting_decisions_.clear();
  }
  // The place the log ends in is put to TSBI as a new area would be (the
  // sequential HybridFilter::finish does the same), unless the robot
  // entered an area at the last step.
  if (options_.hybrid.end_of_log_event && event_applied_step_ != current_step()) {
    KeyframeMsg m;
    m.step = current_step();
    m.end_of_log = true;
    ++aam_outstanding_;
    if (!aam_.post(std::move(m))) throw Error(ExitCode::kInternal, "area abstraction stopped");
    const DecisionMsg d = wait_reply(decisions_, "area abstraction");
    if (d.decision.new_area) filter_.keep_most_probable();
    on_decision(d);
    while (event_in_flight_) on_event_result(wait_reply(event_results_, "topological inference"));
  }
  // The results applied here may settle a hypothesis, as after any step.
  accept_if_dominant();
  while (alignments_outstanding_ > 0)
    on_alignment_result(wait_reply(alignment_results_, "loop-closure acceptance"));
  if (!traces_.empty()) {
    StepTrace& last = traces_.back();
    last.map_memory_bytes = filter_.map_memory_bytes();
    last.peak_rss_bytes = peak_rss_bytes();
  }
}

void HmtSystem::record_step(uint64_t index, double time, bool sample_memory) {
  const std::vector<double> p = filter_.probabilities();
  const auto& hyps = filter_.hypotheses();
  StepTrace t;
  t.step = index;
  t.time = time;
  t.pmf = filter_.position_pmf();
  TopologySummary topo;
  for (size_t i = 0; i < hyps.size(); ++i) {
    const hybrid::Hypothesis& h = hyps[i];
    t.hypotheses.push_back({h.id, p[i], h.current_area(), h.filter.ess(),
                            h.filter.particles().size()});
    topo.hypotheses.push_back({h.id, p[i], h.current_area(), h.map.area_count()});
  }
  if (sample_memory) {
    t.map_memory_bytes = filter_.map_memory_bytes();
    t.peak_rss_bytes = peak_rss_bytes();
  }
  const hybrid::Hypothesis& best = filter_.best();
  MetricEstimate e;
  e.valid = true;
  e.step = index;
  e.time = time;
  e.area = best.current_area();
  e.pose_in_area = best.filter.best().estimates.back();
  e.pose_continuous = best.in_keyframes(e.pose_in_area);
  e.ess = best.filter.ess();
  e.hypotheses = hyps.size();
  topo.pmf = t.pmf;
  topo.transitions = filter_.transitions().size();
  topo.closures_accepted = filter_.stats().loop_closures_accepted;
  topo.best_areas = best.map.area_count();
  t.areas = topo.best_areas;
  traces_.push_back(std::move(t));
  topo_layer_.publish(std::move(topo));
  metric_layer_.end_step(e);
}

// ------------------------------------------------------ the other processes

void HmtSystem::on_keyframe(KeyframeMsg& m) {
  const Clock::time_point t0 = Clock::now();
  DecisionMsg d;
  d.step = m.step;
  if (m.end_of_log) {
    d.decision = partitioner_.end_of_log();
  } else {
    partitioner_.add_keyframe(std::move(m.keyframe));
    d.decision = partitioner_.update();
    area_layer_.record_keyframe(m.step, d.decision.new_area);
  }
  add_time(times_.aam, m.step, ms_since(t0));
  if (!decisions_.push(std::move(d))) throw Error(ExitCode::kInternal, "metric SLAM stopped");
}

void HmtSystem::on_event(EventMsg& m) {
  if (event_hook_) event_hook_(m.step);
  const Clock::time_point t0 = Clock::now();
  m.outcomes = filter_.evaluate(m.inputs, &m.considered);
  add_time(times_.tsbi, m.step, ms_since(t0));
  if (!event_results_.push(std::move(m))) throw Error(ExitCode::kInternal, "metric SLAM stopped");
}

void HmtSystem::on_alignment(AlignmentMsg& m) {
  const Clock::time_point t0 = Clock::now();
  m.reports = filter_.align(m.job);
  add_time(times_.tlca, m.job.step, ms_since(t0));
  if (!alignment_results_.push(std::move(m)))
    throw Error(ExitCode::kInternal, "metric SLAM stopped");
}

}  // namespace hmt::framework

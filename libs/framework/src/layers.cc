#include "hmt/framework/layers.h"

#include <utility>

namespace hmt::framework {

void MetricLayer::begin_step(uint64_t step) {
  std::lock_guard<std::mutex> lock(mutex_);
  busy_ = true;
  busy_step_ = step;
  busy_since_ = std::chrono::steady_clock::now();
}

void MetricLayer::end_step(const MetricEstimate& estimate) {
  std::lock_guard<std::mutex> lock(mutex_);
  estimate_ = estimate;
  busy_ = false;
}

MetricEstimate MetricLayer::estimate() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return estimate_;
}

MetricBusy MetricLayer::busy() const {
  std::lock_guard<std::mutex> lock(mutex_);
  MetricBusy b;
  b.busy = busy_;
  b.step = busy_step_;
  if (busy_)
    b.for_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() -
                                                         busy_since_).count();
  return b;
}

void AreaLayer::record_keyframe(uint64_t step, bool new_area) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++summary_.keyframes;
  if (new_area) {
    ++summary_.new_area_decisions;
    summary_.last_decision_step = step;
  }
}

AreaSummary AreaLayer::summary() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return summary_;
}

void TopologicalLayer::publish(TopologySummary summary) {
  std::lock_guard<std::mutex> lock(mutex_);
  summary_ = std::move(summary);
}

TopologySummary TopologicalLayer::summary() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return summary_;
}

}  // namespace hmt::framework

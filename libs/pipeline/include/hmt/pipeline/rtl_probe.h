// A probe of real-time localization during a run: a thread that asks RTL
// for the pose `hz` times a second and records how long the answer took and
// what metric SLAM was doing at that moment (rtl.csv). It shows that RTL
// answers at once while metric SLAM is in the middle of a long step.
#pragma once

#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "hmt/framework/hmt_system.h"

namespace hmt::pipeline {

struct RtlSample {
  double wall_s = 0.0;      // since the probe started
  double latency_ms = 0.0;  // from the request to the answer
  framework::MetricBusy busy;  // metric SLAM when the request was made
  // Metric SLAM was still on that same step when the answer came.
  bool answered_during_step = false;
  double step_running_ms = 0.0;  // how long that step had run by then
  framework::RtlPose pose;
};

class RtlProbe {
 public:
  // Starts probing `system` (already started); hz > 0.
  RtlProbe(framework::HmtSystem& system, double hz);
  ~RtlProbe() { stop(); }
  // Stops and joins; idempotent.
  void stop();
  // After stop().
  const std::vector<RtlSample>& samples() const { return samples_; }

 private:
  void run();

  framework::HmtSystem& system_;
  const double period_s_;
  std::mutex mutex_;            // guards stop_
  std::condition_variable wake_;  // stop() was called
  bool stop_ = false;
  std::vector<RtlSample> samples_;  // probe thread only, until joined
  std::thread thread_;
};

void write_rtl_csv(const std::string& path, const std::vector<RtlSample>& samples);

}  // namespace hmt::pipeline

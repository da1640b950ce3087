#include "hmt/pipeline/rtl_probe.h"

#include <chrono>
#include <cstdio>
#include <sstream>

#include "hmt/common/files.h"

namespace hmt::pipeline {

using Clock = std::chrono::steady_clock;

RtlProbe::RtlProbe(framework::HmtSystem& system, double hz)
    : system_(system), period_s_(1.0 / hz), thread_([this] { run(); }) {}

void RtlProbe::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void RtlProbe::run() {
  const Clock::time_point t0 = Clock::now();
  Clock::time_point next = t0;
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stop_) {
    lock.unlock();
    RtlSample s;
    const Clock::time_point asked = Clock::now();
    s.wall_s = std::chrono::duration<double>(asked - t0).count();
    s.busy = system_.metric_layer().busy();
    try {
      s.pose = system_.locate().get();
      s.latency_ms = std::chrono::duration<double, std::milli>(Clock::now() - asked).count();
      const framework::MetricBusy after = system_.metric_layer().busy();
      s.answered_during_step = s.busy.busy && after.busy && after.step == s.busy.step;
      if (s.answered_during_step) s.step_running_ms = after.for_ms;
      samples_.push_back(s);
    } catch (const std::exception&) {
      // RTL has stopped (the run is over or failed): nothing more to ask.
      lock.lock();
      break;
    }
    next += std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(period_s_));
    lock.lock();
    // The probe's rate, not a synchronisation: stop() wakes it at once.
    wake_.wait_until(lock, next, [&] { return stop_; });
  }
}

void write_rtl_csv(const std::string& path, const std::vector<RtlSample>& samples) {
  std::ostringstream o;
  o << "wall_s,latency_ms,metric_busy,busy_step,busy_for_ms,answered_during_step,"
       "step_running_ms,valid,estimate_step,pending_odometry,area,x,y,theta\n";
  char line[256];
  for (const RtlSample& s : samples) {
    std::snprintf(line, sizeof line, "%.6f,%.4f,%d,%llu,%.3f,%d,%.3f,%d,%llu,%zu,%u,%.6f,%.6f,%.6f\n",
                  s.wall_s, s.latency_ms, s.busy.busy ? 1 : 0,
                  static_cast<unsigned long long>(s.busy.step), s.busy.for_ms,
                  s.answered_during_step ? 1 : 0, s.step_running_ms,
                  s.pose.valid ? 1 : 0, static_cast<unsigned long long>(s.pose.estimate_step),
                  s.pose.pending_odometry, s.pose.area, s.pose.pose_in_area.x,
                  s.pose.pose_in_area.y, s.pose.pose_in_area.theta);
    o << line;
  }
  write_text_atomically(path, o.str());
}

}  // namespace hmt::pipeline

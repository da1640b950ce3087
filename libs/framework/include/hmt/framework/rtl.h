// Real-time localization (RTL, 002 Sec. V): the robot's pose at any moment,
// the latest estimate of metric SLAM composed with the odometry that has
// arrived since (the steps still queued for metric SLAM). Its own thread,
// so it answers while metric SLAM is busy with a long step.
#pragma once

#include <cstdint>
#include <deque>
#include <future>
#include <utility>

#include "hmt/common/pose2d.h"
#include "hmt/framework/layers.h"
#include "hmt/framework/process.h"

namespace hmt::framework {

struct RtlPose {
  bool valid = false;            // false before metric SLAM's first step
  uint64_t estimate_step = 0;    // the step of the estimate it starts from
  size_t pending_odometry = 0;   // odometry increments composed onto it
  topology::AreaId area = topology::kNoArea;
  Pose2D pose_in_area;
  Pose2D pose_continuous;        // in the area abstraction's frame
};

class RealTimeLocalizer {
 public:
  RealTimeLocalizer(const MetricLayer& layer, size_t capacity);
  void start() { process_.start(); }
  void stop() { process_.stop(); }
  // The odometry of log step `step` (robot frame, since the previous step),
  // as it is read, before metric SLAM processes it.
  void odometry(uint64_t step, const Pose2D& increment);
  // The pose now. The future fails if RTL has stopped.
  std::future<RtlPose> request();

 private:
  struct Msg {
    bool query = false;
    uint64_t step = 0;
    Pose2D increment;
    std::promise<RtlPose> reply;
  };
  void handle(Msg& m);
  void forget_until(uint64_t step);

  const MetricLayer& layer_;
  std::deque<std::pair<uint64_t, Pose2D>> odometry_;  // RTL thread only
  Process<Msg> process_;
};

}  // namespace hmt::framework

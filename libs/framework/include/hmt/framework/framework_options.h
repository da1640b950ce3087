// Options of the concurrent framework ([framework]).
#pragma once

#include <string>

#include "hmt/common/config.h"

namespace hmt::framework {

enum class Mode {
  // Metric SLAM hands each keyframe to the area abstraction and waits for
  // its answer, and waits for TSBI and TLCA at every event they handle
  // (hand-shaking): the same log, config and seed give byte-identical
  // results whatever the thread timing, identical to the sequential filter.
  kDeterministic,
  // Metric SLAM never waits: the answers of the other processes are applied
  // at the first step after they arrive (TSBI's carried forward by each
  // particle's motion since its snapshot), as on a robot.
  kLive,
};

struct FrameworkOptions {
  Mode mode = Mode::kDeterministic;
  // Messages each process's inbox holds before its producer waits.
  int inbox_capacity = 64;
  // Live mode on a recorded log: playback speed against the log's clock
  // (1 = real time, as the robot recorded it; 0 = as fast as it is read).
  double live_speed = 1.0;
  // Queries to RTL per second during a run, logged to rtl.csv (0 = none).
  double rtl_probe_hz = 0.0;
  // Reads [framework] mode = deterministic | live, inbox_capacity,
  // live_speed, rtl_probe_hz.
  void load(Config& cfg, const std::string& section = "framework");
};

}  // namespace hmt::framework

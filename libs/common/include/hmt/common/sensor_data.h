// The one internal stream every log format is turned into: a sequence of
// steps, each an odometry increment since the previous step followed by one
// planar range scan.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hmt/common/pose2d.h"

namespace hmt {

struct LaserScan {
  double timestamp = 0.0;        // seconds (log clock)
  float angle_min = 0.0f;        // bearing of beam 0 in the sensor frame (rad)
  float angle_increment = 0.0f;  // between consecutive beams (rad)
  float max_range = 0.0f;        // readings >= this are "no return"
  std::vector<float> ranges;     // metres; one per beam
  std::vector<uint8_t> valid;    // 1 = a real return, 0 = no return / invalid
  Pose2D sensor_pose;            // sensor in the robot frame

  size_t size() const { return ranges.size(); }
  float bearing(size_t i) const {
    return angle_min + angle_increment * static_cast<float>(i);
  }
};

struct LogStep {
  double timestamp = 0.0;      // timestamp of the scan
  Pose2D odometry_increment;   // robot motion since the previous step
  bool has_odometry = false;   // false only for the very first step
  LaserScan scan;
};

// A whole log in memory, with where it came from (for messages).
struct Log {
  std::string source;
  std::vector<LogStep> steps;
};

}  // namespace hmt

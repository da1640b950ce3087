// Options of the offline grouping tool (hmt-partition), INI section
// [grouping]. The tool also reads [input], [output], [grid], [scan_matcher]
// and [area] through the shared job options, so one configuration file serves
// hmt-slam and hmt-partition alike.
#pragma once

#include <string>

namespace hmt {
class Config;
}

namespace hmt::grouping {

struct GroupingOptions {
  // A scan becomes a keyframe (a node of the observation graph) when the
  // robot has moved at least this far [m] or turned at least this much [rad]
  // since the last keyframe. Spacing keyframes by motion rather than by time
  // keeps the graph's density along the route independent of the robot's
  // speed: a robot standing still would otherwise add a clique of identical
  // scans whose weight biases every normalized cut. 0.5 m and 0.5 rad (~29
  // deg) both keep roughly 80% of a 180-degree scan's sensed space from one
  // keyframe to the next. Reaching either is enough (as for [metric_slam]
  // map_update_*), so 0 for either makes every scan a keyframe.
  double keyframe_distance = 0.5;
  double keyframe_angle = 0.5;
  // With a trajectory file, a scan takes the pose whose timestamp is nearest
  // to its own if they differ by at most this [s]; scans without one are
  // skipped (and counted in summary.json).
  double pose_time_tolerance = 0.01;
  // Step 3 of 001 Sec. IV ("run a map building algorithm" per group): each
  // group's keyframes are registered in turn against the group's local map
  // with the scan matcher of [scan_matcher], starting from the given
  // relative poses. false: the local maps use the given poses as they are.
  bool refine_local_maps = true;

  // Reads the keys above from `section`, keeping the current values as
  // defaults, then validates.
  void load(Config& cfg, const std::string& section = "grouping");
  // Throws ConfigError naming the section and key of the first bad value.
  void validate(const std::string& section = "grouping") const;
};

}  // namespace hmt::grouping

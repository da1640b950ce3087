// Keyframe selection: which scans of the log become nodes of the observation
// graph (001 Eq. 14).
#pragma once

#include <vector>

#include "hmt/area/keyframe.h"
#include "hmt/common/pose2d.h"
#include "hmt/common/sensor_data.h"
#include "hmt/grouping/scan_poses.h"

namespace hmt::grouping {

using area::kMinKeyframeReturns;

struct KeyframeRecord {
  int scan = 0;            // index of the scan in the log
  double timestamp = 0.0;  // the scan's
  Pose2D pose;             // robot pose, common frame
};

struct KeyframeSelection {
  std::vector<KeyframeRecord> keyframes;  // in log order
  size_t too_few_returns = 0;  // scans that qualified by motion but were
                               // skipped for kMinKeyframeReturns
};

// Walks the scans that have a pose in log order: the first one with enough
// returns is a keyframe, then every one whose pose is at least `distance`
// metres or `angle` radians away from the last keyframe's (the convention of
// [metric_slam] map_update_distance / map_update_angle: reaching either
// threshold is enough, so a 0 for either makes every scan a keyframe).
KeyframeSelection select_keyframes(const Log& log, const ScanPoses& poses,
                                   double distance, double angle);

// The keyframes as input to the area library (exact poses: the fixed-delta
// SSO of 001 Eq. 16 does not use covariances).
std::vector<area::Keyframe> area_keyframes(
    const Log& log, const std::vector<KeyframeRecord>& keyframes);

}  // namespace hmt::grouping

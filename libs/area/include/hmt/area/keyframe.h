// A keyframe of the auxiliary observation graph (001 Eq. 14): the robot pose
// (with its uncertainty, used by the probabilistic SSO) and the scan taken
// there.
#pragma once

#include <cstddef>

#include "hmt/area/pose_gaussian.h"
#include "hmt/common/sensor_data.h"

namespace hmt::area {

struct Keyframe {
  PoseGaussian pose;  // robot pose in a common frame (area or global)
  LaserScan scan;
  // For the placement criterion (placement.h, 003 Eq. 3), filled only when
  // the policy uses it: the robot's accumulated position error since the
  // current area's origin (epsilon, metres) and the scan's distinctiveness R.
  double uncertainty = 0.0;
  double distinctiveness = 0.0;
};

// A scan with fewer valid returns (is_valid_return) than this senses too
// little to overlap with anything: it would become an isolated node, a group
// of its own, so it is never a keyframe.
constexpr size_t kMinKeyframeReturns = 20;
size_t valid_returns(const LaserScan& scan);
inline bool enough_returns(const LaserScan& scan) {
  return valid_returns(scan) >= kMinKeyframeReturns;
}

}  // namespace hmt::area

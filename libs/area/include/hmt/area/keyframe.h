// A keyframe of the auxiliary observation graph (001 Eq. 14): the robot pose
// (with its uncertainty, used by the probabilistic SSO) and the scan taken
// there.
#pragma once

#include "hmt/area/pose_gaussian.h"
#include "hmt/common/sensor_data.h"

namespace hmt::area {

struct Keyframe {
  PoseGaussian pose;  // robot pose in a common frame (area or global)
  LaserScan scan;
};

}  // namespace hmt::area

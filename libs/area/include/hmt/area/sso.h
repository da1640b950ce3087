// SSO of observations made of several sensors: the average of the SSO of each
// sensor (000 Sec. 6.2: "the corresponding SSO is computed by averaging the
// individual SSO functions").
#pragma once

#include <vector>

#include "hmt/area/landmark_sso.h"
#include "hmt/area/scan_sso.h"

namespace hmt::area {

// One keyframe's observation: any number of range scans and landmark sets.
// Sensor k of one observation is compared with sensor k of the other.
struct Observation {
  std::vector<LaserScan> scans;
  std::vector<LandmarkObservation> landmark_sets;
};

// Mean of the per-sensor SSOs over the sensors that sensed something in at
// least one of the two observations (a sensor with no valid return or no
// landmark on either side says nothing about overlap and is left out); 0 when
// no sensor sensed anything. Throws std::invalid_argument when the two
// observations do not have the same number of scans and landmark sets.
double observation_sso(const Observation& a, const PoseGaussian& pose_a,
                       const Observation& b, const PoseGaussian& pose_b,
                       const SsoOptions& options);

}  // namespace hmt::area

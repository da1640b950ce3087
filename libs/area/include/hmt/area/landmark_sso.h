// Sensed-space overlap of two landmark observations (000 Sec. 3.1).
//
// Each observation is a set of landmarks with Gaussian positions in the
// robot frame of the keyframe that observed them. Landmark i of A and j of B
// are the same map element when (000 Eq. 15)
//   eps = (x_B - x_A) (+) z_B^j - z_A^i
// is near zero: its squared Mahalanobis distance under the first-order
// covariance (relative pose, both landmark covariances) must be <= gate, and,
// when both carry descriptors and options.descriptor_threshold > 0, their
// Euclidean descriptor distance must be <= descriptor_threshold.
//
// The distance is evaluated in A's frame and in B's frame and averaged: to
// first order the two are equal (eps_BA = -R^T eps_AB, Cov_BA = R^T Cov_AB R),
// and the average makes the SSO exactly symmetric.
//
// A map element is counted once (Eq. 13 counts elements of the sets M(z)), so
// matches are one-to-one: greedily by increasing distance. With m matches,
//   SSO = m / ((n_A + n_B) / 2),
// the matches over the average landmark count: 1 for identical observations,
// 0 for disjoint ones, in [0, 1] and symmetric. (Eq. 13's intersection over
// union would be m / (n_A + n_B - m); the average-count form is on the same
// scale as the scan SSO of 001 Eq. 18 and is the one used here.)
#pragma once

#include <Eigen/Core>
#include <vector>

#include "hmt/area/area_options.h"
#include "hmt/area/pose_gaussian.h"

namespace hmt::area {

struct Landmark {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();  // robot frame [m]
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  std::vector<float> descriptor;  // empty: none
};

struct LandmarkObservation {
  std::vector<Landmark> landmarks;
};

// A landmark observed at range r and bearing phi (in the sensor frame) by a
// sensor at `sensor_pose` on the robot, with the given noise, as a Gaussian
// in the robot frame.
Landmark landmark_from_range_bearing(const Pose2D& sensor_pose, double range,
                                     double bearing, double range_std,
                                     double bearing_std);

// Number of one-to-one matches between A and B (see above).
size_t count_landmark_matches(const LandmarkObservation& a,
                              const PoseGaussian& pose_a,
                              const LandmarkObservation& b,
                              const PoseGaussian& pose_b,
                              const SsoOptions& options);

// m / ((n_A + n_B) / 2); 0 when both are empty.
double landmark_sso(const LandmarkObservation& a, const PoseGaussian& pose_a,
                    const LandmarkObservation& b, const PoseGaussian& pose_b,
                    const SsoOptions& options);

}  // namespace hmt::area

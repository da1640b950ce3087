// Small builders shared by the topology tests.
#pragma once

#include <Eigen/Core>

#include "hmt/common/pose2d.h"

namespace hmt::topology::testing_util {

// Covariance of (x, y, theta) from standard deviations and correlations.
inline Eigen::Matrix3d cov_of(double sx, double sy, double st, double rxy = 0.0,
                              double rxt = 0.0, double ryt = 0.0) {
  Eigen::Matrix3d c;
  c << sx * sx, rxy * sx * sy, rxt * sx * st,  //
      rxy * sx * sy, sy * sy, ryt * sy * st,   //
      rxt * sx * st, ryt * sy * st, st * st;
  return c;
}

inline Eigen::Matrix3d diag(double sx, double sy, double st) { return cov_of(sx, sy, st); }

inline Eigen::Vector3d vec(const Pose2D& p) { return {p.x, p.y, p.theta}; }

}  // namespace hmt::topology::testing_util

// The first-order propagation of Gaussian poses the SSO needs: the relative
// pose between two keyframes (000 Eq. 15) and the composition of a pose
// with a point (the Jacobian J of 000 Eq. 16).
#pragma once

#include <Eigen/Core>

#include "hmt/common/pose2d.h"
#include "hmt/common/pose_gaussian.h"

namespace hmt::area {

using PoseGaussian = hmt::PoseGaussian;  // hmt/common/pose_gaussian.h

// `of` seen from the frame of `from` (of - from), with covariance propagated
// to first order assuming the two poses are independent.
PoseGaussian relative_pose(const PoseGaussian& of, const PoseGaussian& from);

// d(q (+) p) / dq for a point p: 2x3.
Eigen::Matrix<double, 2, 3> jacobian_pose_point_wrt_pose(const Pose2D& q,
                                                         const Point2D& p);

// Covariance of the point q (+) p for a Gaussian pose q and a point p with
// covariance cov_p given in q's frame: J_q Sigma_q J_q^T + R cov_p R^T.
Eigen::Matrix2d compose_point_cov(const PoseGaussian& q, const Point2D& p,
                                  const Eigen::Matrix2d& cov_p);

// Covariance, in the sensor frame, of the point (r cos phi, r sin phi) for
// range and bearing noise: J diag(sr^2, sphi^2) J^T.
Eigen::Matrix2d range_bearing_cov(double r, double phi, double range_std,
                                  double bearing_std);

inline Eigen::Matrix2d rotation(double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  Eigen::Matrix2d R;
  R << c, -s, s, c;
  return R;
}

}  // namespace hmt::area

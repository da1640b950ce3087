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

// compose_point_cov() and Pose2D::transform() for many points through one
// pose, its cosine and sine taken once instead of three times a point (the
// SSO's inner loop). The same arithmetic in the same order: the same bits.
class PointComposer {
 public:
  explicit PointComposer(const PoseGaussian& q)
      : q_(q), c_(std::cos(q.mean.theta)), s_(std::sin(q.mean.theta)) {
    R_ << c_, -s_, s_, c_;
  }
  Point2D transform(const Point2D& p) const {
    return {q_.mean.x + c_ * p.x - s_ * p.y, q_.mean.y + s_ * p.x + c_ * p.y};
  }
  // d(q (+) p) / dq: 2x3.
  Eigen::Matrix<double, 2, 3> jacobian(const Point2D& p) const {
    Eigen::Matrix<double, 2, 3> J;
    J << 1, 0, -s_ * p.x - c_ * p.y, 0, 1, c_ * p.x - s_ * p.y;
    return J;
  }
  Eigen::Matrix2d cov(const Point2D& p, const Eigen::Matrix2d& cov_p) const {
    const Eigen::Matrix<double, 2, 3> J = jacobian(p);
    return J * q_.cov * J.transpose() + R_ * cov_p * R_.transpose();
  }

 private:
  PoseGaussian q_;  // a copy: the composer may outlive the caller's pose
  double c_, s_;
  Eigen::Matrix2d R_;
};

}  // namespace hmt::area

// A planar pose with a Gaussian uncertainty, N(mean, cov): the one type the
// area abstraction (keyframe poses, libs/area) and the topological layer
// (arcs, TSBI's matches, libs/topology) share. Each library keeps the
// operations it needs next to its own use of the type.
//
// Parameterisation: cov is the covariance of the vector (x, y, theta) with
// additive perturbations; a sample is (mean.x + e_x, mean.y + e_y,
// wrap(mean.theta + e_theta)), e ~ N(0, cov).
#pragma once

#include <Eigen/Core>

#include "hmt/common/pose2d.h"

namespace hmt {

struct PoseGaussian {
  Pose2D mean;
  // Covariance of (x, y, theta): symmetric, positive semi-definite. Zero
  // means "exactly known".
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();

  PoseGaussian() = default;
  explicit PoseGaussian(const Pose2D& m,
                        const Eigen::Matrix3d& c = Eigen::Matrix3d::Zero())
      : mean(m), cov(c) {}
};

// `p` moved by the additive perturbation e = (e_x, e_y, e_theta) of the
// parameterisation above.
inline Pose2D perturbed(const Pose2D& p, const Eigen::Vector3d& e) {
  return Pose2D(p.x + e.x(), p.y + e.y(), wrap_angle(p.theta + e.z()));
}

}  // namespace hmt

// The relative-pose constraint both pose graphs of this library are made of
// (optimize_poses() over the areas, optimize_keyframe_graph() over areas and
// keyframes), linearised once here: the residual
//   h(x_a, x_b) = difference((-)x_a (+) x_b, mean)
// and its Jacobians with respect to both ends (normal_equations.h sums
// them into H and g).
//
// With c = cos(theta_a), s = sin(theta_a), d = t_b - t_a:
//   dh/dx_a = [ -c -s  -s d_x + c d_y ]    dh/dx_b = [  c  s  0 ]
//             [  s -c  -c d_x - s d_y ]              [ -s  c  0 ]
//             [  0  0        -1       ]              [  0  0  1 ]
// (the wrap of the angle has derivative 1 wherever it is defined).
#pragma once

#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>
#include <cmath>
#include <stdexcept>
#include <string>

#include "hmt/common/pose2d.h"
#include "hmt/topology/pose_gaussian.h"

namespace hmt::global_map {

using SparseMatrix = Eigen::SparseMatrix<double>;
using Cholesky = Eigen::CholmodDecomposition<SparseMatrix, Eigen::Lower>;

struct LinearisedRelativePose {
  Eigen::Vector3d residual;
  Eigen::Matrix3d d_from;
  Eigen::Matrix3d d_to;
};

inline Eigen::Vector3d relative_pose_residual(const Pose2D& from, const Pose2D& to,
                                              const Pose2D& mean) {
  return topology::difference(to - from, mean);
}

inline LinearisedRelativePose linearise_relative_pose(const Pose2D& from, const Pose2D& to,
                                                      const Pose2D& mean) {
  const double c = std::cos(from.theta), s = std::sin(from.theta);
  const double dx = to.x - from.x, dy = to.y - from.y;
  LinearisedRelativePose l;
  l.residual = relative_pose_residual(from, to, mean);
  l.d_from << -c, -s, -s * dx + c * dy,  //
      s, -c, -c * dx - s * dy,           //
      0, 0, -1;
  l.d_to << c, s, 0,  //
      -s, c, 0,       //
      0, 0, 1;
  return l;
}

// Factorises H; `who` names the caller in the error when H is not positive
// definite.
inline void factorize(Cholesky& cholesky, const SparseMatrix& H, const char* who) {
  cholesky.factorize(H);
  if (cholesky.info() != Eigen::Success)
    throw std::runtime_error(std::string(who) +
                             ": the information matrix is not positive definite");
}

}  // namespace hmt::global_map

// The relative-pose constraint both pose graphs of this library are made of
// (optimize_poses() over the areas, optimize_keyframe_graph() over areas and
// keyframes), linearised once here: the residual
//   h(x_a, x_b) = difference((-)x_a (+) x_b, mean)
// and its Jacobians with respect to both ends, and the accumulation of
// J^T Omega J and J^T Omega e into sparse normal equations.
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
#include <vector>

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

struct NormalEquations {
  SparseMatrix H;
  Eigen::VectorXd g;
};

// H = sum J^T Omega J and g = sum J^T Omega e over the constraints added,
// with the blocks of the fixed root (first column -1) left out. Only H's
// lower triangle is stored: it is all the Cholesky (Eigen::Lower) reads,
// and the triplets of the upper one had doubled the builder's memory (on a
// graph of 60 000 constraints, tens of MB at every iteration). Constraints
// added in the same order give the same triplet positions every time, so
// the pattern (and CHOLMOD's symbolic analysis of it) stays the same
// across iterations.
class NormalEquationsBuilder {
 public:
  NormalEquationsBuilder(int unknowns, size_t constraints) : g_(Eigen::VectorXd::Zero(unknowns)) {
    triplets_.reserve(constraints * (6 + 6 + 9));
  }

  // One constraint between the variables whose first columns are a and b.
  void add(int a, int b, const LinearisedRelativePose& l, const Eigen::Matrix3d& omega) {
    const Eigen::Matrix3d Ja_t_omega = l.d_from.transpose() * omega;
    const Eigen::Matrix3d Jb_t_omega = l.d_to.transpose() * omega;
    add_block(a, a, Ja_t_omega * l.d_from);
    if (a > b)
      add_block(a, b, Ja_t_omega * l.d_to);
    else
      add_block(b, a, Jb_t_omega * l.d_from);
    add_block(b, b, Jb_t_omega * l.d_to);
    if (a >= 0) g_.segment<3>(a) += Ja_t_omega * l.residual;
    if (b >= 0) g_.segment<3>(b) += Jb_t_omega * l.residual;
  }

  NormalEquations build() {
    NormalEquations eq;
    eq.g = std::move(g_);
    eq.H.resize(eq.g.size(), eq.g.size());
    eq.H.setFromTriplets(triplets_.begin(), triplets_.end());
    return eq;
  }

 private:
  // The block's entries on or below the diagonal (a block on the diagonal
  // keeps 6 of its 9, one below keeps them all).
  void add_block(int row, int col, const Eigen::Matrix3d& block) {
    if (row < 0 || col < 0) return;  // a block of the fixed root
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (row + i >= col + j) triplets_.emplace_back(row + i, col + j, block(i, j));
  }

  std::vector<Eigen::Triplet<double>> triplets_;
  Eigen::VectorXd g_;
};

// Factorises H; `who` names the caller in the error when H is not positive
// definite.
inline void factorize(Cholesky& cholesky, const SparseMatrix& H, const char* who) {
  cholesky.factorize(H);
  if (cholesky.info() != Eigen::Success)
    throw std::runtime_error(std::string(who) +
                             ": the information matrix is not positive definite");
}

}  // namespace hmt::global_map

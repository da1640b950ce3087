// The sparse normal equations H dx = -g of a pose graph made of
// relative-pose constraints (relative_pose_factor.h): H = sum J^T Omega J,
// g = sum J^T Omega e, with the blocks of the fixed root left out.
//
// H's pattern is built once, from which variables each constraint joins,
// and every Gauss-Newton iteration then adds its blocks straight into H's
// values. Only the lower triangle is stored: it is all the Cholesky
// (Eigen::Lower) reads. Assembling from triplets instead had cost, at every
// iteration, 21 triplets of 16 bytes a constraint and the sort's copy of
// them (on the five-lap soak's keyframe graph, 47 000 constraints, over
// 20 MB above the graph itself); the pattern and the sums are the same.
#pragma once

#include <Eigen/Sparse>
#include <utility>
#include <vector>

#include "relative_pose_factor.h"

namespace hmt::global_map {

class NormalEquations {
 public:
  // Constraint k joins the variables whose first columns are pairs[k]
  // (multiples of 3; -1 for the fixed root). Every variable in [0, unknowns)
  // that no constraint names gets no diagonal block, so H is singular then.
  NormalEquations(int unknowns, const std::vector<std::pair<int, int>>& pairs);

  // Zeroes H and g; add() then sums the constraints.
  void clear();
  // Constraint k linearised, and its information matrix. Adding them in
  // order 0, 1, ... sums each entry of H in the order of the constraints.
  void add(size_t k, const LinearisedRelativePose& l, const Eigen::Matrix3d& omega);

  const SparseMatrix& H() const { return H_; }
  const Eigen::VectorXd& g() const { return g_; }

 private:
  // Adds to the diagonal block of the variable whose first column is a, or
  // to the index-th block below the diagonal in the columns from col.
  void add_diagonal(int a, const Eigen::Matrix3d& block);
  void add_below(int col, int index, const Eigen::Matrix3d& block);

  struct Constraint {
    int a, b;   // first columns, -1 for the root
    int below;  // which block below the diagonal of column min(a, b) it fills
  };
  std::vector<Constraint> constraints_;
  SparseMatrix H_;
  Eigen::VectorXd g_;
};

}  // namespace hmt::global_map

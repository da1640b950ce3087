// The normalized cut of a two-way split of a weighted graph (000 Eq. 1-3):
//   Ncut(A, B) = cut(A, B) / assoc(A, V) + cut(A, B) / assoc(B, V)
// in [0, 2]. The weight matrix is sparse, symmetric, with non-negative
// weights; its diagonal (a node's weight with itself) is ignored everywhere,
// as in 000 Eq. 21 ("the reflexive arc ... is not employed").
#pragma once

#include <Eigen/SparseCore>
#include <vector>

namespace hmt::area {

using WeightMatrix = Eigen::SparseMatrix<double>;  // column-major

struct CutValues {
  double cut = 0.0;      // sum of weights between A and B
  double assoc_a = 0.0;  // sum of degrees in A
  double assoc_b = 0.0;  // sum of degrees in B
  // The Ncut. A term with a zero cut is 0 (also when its assoc is 0: a group
  // of isolated nodes is perfectly separated).
  double ncut() const {
    if (cut <= 0.0) return 0.0;
    return cut / assoc_a + cut / assoc_b;
  }
};

// in_a[i] != 0 puts node i in A. Throws std::invalid_argument on a size
// mismatch.
CutValues cut_values(const WeightMatrix& W, const std::vector<char>& in_a);
double normalized_cut(const WeightMatrix& W, const std::vector<char>& in_a);

// Degrees d_i = sum_{j != i} w_ij.
Eigen::VectorXd degrees(const WeightMatrix& W);

// Connected components over edges of positive weight (diagonal ignored):
// component label per node, labels numbered by their smallest node.
std::vector<int> connected_components(const WeightMatrix& W, int* count);

// W restricted to `nodes` (in that order), diagonal dropped.
WeightMatrix submatrix(const WeightMatrix& W, const std::vector<int>& nodes);

// Throws std::invalid_argument unless W is square with finite non-negative
// entries and symmetric (to a relative 1e-9).
void check_weight_matrix(const WeightMatrix& W);

}  // namespace hmt::area

#include "normal_equations.h"

#include <algorithm>
#include <cstdint>
#include <stdexcept>

namespace hmt::global_map {

// Column c = 3 v + j (j = 0, 1, 2) of H holds, in row order: the rows
// 3 v + j .. 3 v + 2 of variable v's diagonal block, then the three rows of
// each block below it, by increasing block row. A variable that has a block
// below its diagonal also has its diagonal block (the same constraint adds
// both).
NormalEquations::NormalEquations(int unknowns, const std::vector<std::pair<int, int>>& pairs)
    : g_(Eigen::VectorXd::Zero(unknowns)) {
  if (unknowns % 3 != 0) throw std::invalid_argument("NormalEquations: unknowns not 3 per pose");
  const int V = unknowns / 3;
  auto variable = [&](int column) {
    if (column < -1 || column >= unknowns || (column >= 0 && column % 3 != 0))
      throw std::invalid_argument("NormalEquations: a column outside the unknowns");
    return column < 0 ? -1 : column / 3;
  };
  std::vector<char> diagonal(static_cast<size_t>(V), 0);
  // The blocks below the diagonal as (column variable, row variable).
  std::vector<std::pair<int, int>> below;
  below.reserve(pairs.size());
  for (const auto& [a, b] : pairs) {
    const int va = variable(a), vb = variable(b);
    if (va >= 0) diagonal[static_cast<size_t>(va)] = 1;
    if (vb >= 0) diagonal[static_cast<size_t>(vb)] = 1;
    if (va >= 0 && va == vb)
      throw std::invalid_argument("NormalEquations: a constraint between a pose and itself");
    if (va >= 0 && vb >= 0) below.emplace_back(std::min(va, vb), std::max(va, vb));
  }
  std::sort(below.begin(), below.end());
  below.erase(std::unique(below.begin(), below.end()), below.end());
  // first[v]: where variable v's blocks start in `below`.
  std::vector<int> first(static_cast<size_t>(V) + 1, 0);
  for (const auto& blk : below) ++first[static_cast<size_t>(blk.first) + 1];
  for (int v = 0; v < V; ++v) first[static_cast<size_t>(v) + 1] += first[static_cast<size_t>(v)];

  int64_t nnz = 0;
  for (int v = 0; v < V; ++v)
    nnz += diagonal[static_cast<size_t>(v)] ? 6 + 9 * (first[v + 1] - first[v]) : 0;
  H_.resize(unknowns, unknowns);
  H_.resizeNonZeros(static_cast<Eigen::Index>(nnz));
  int* outer = H_.outerIndexPtr();
  int* inner = H_.innerIndexPtr();
  int at = 0;
  for (int v = 0; v < V; ++v)
    for (int j = 0; j < 3; ++j) {
      outer[3 * v + j] = at;
      if (!diagonal[static_cast<size_t>(v)]) continue;
      for (int i = j; i < 3; ++i) inner[at++] = 3 * v + i;
      for (int k = first[v]; k < first[v + 1]; ++k)
        for (int i = 0; i < 3; ++i) inner[at++] = 3 * below[static_cast<size_t>(k)].second + i;
    }
  outer[unknowns] = at;

  constraints_.reserve(pairs.size());
  for (const auto& [a, b] : pairs) {
    int index = -1;
    if (a >= 0 && b >= 0) {
      const std::pair<int, int> key(std::min(a, b) / 3, std::max(a, b) / 3);
      index = static_cast<int>(std::lower_bound(below.begin() + first[key.first],
                                                below.begin() + first[key.first + 1], key) -
                               (below.begin() + first[key.first]));
    }
    constraints_.push_back({a, b, index});
  }
  clear();
}

void NormalEquations::clear() {
  std::fill(H_.valuePtr(), H_.valuePtr() + H_.nonZeros(), 0.0);
  g_.setZero();
}

void NormalEquations::add_diagonal(int a, const Eigen::Matrix3d& block) {
  double* value = H_.valuePtr();
  const int* outer = H_.outerIndexPtr();
  for (int j = 0; j < 3; ++j)
    for (int i = j; i < 3; ++i) value[outer[a + j] + (i - j)] += block(i, j);
}

void NormalEquations::add_below(int col, int index, const Eigen::Matrix3d& block) {
  double* value = H_.valuePtr();
  const int* outer = H_.outerIndexPtr();
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) value[outer[col + j] + (3 - j) + 3 * index + i] += block(i, j);
}

void NormalEquations::add(size_t k, const LinearisedRelativePose& l,
                          const Eigen::Matrix3d& omega) {
  const Constraint& c = constraints_.at(k);
  const Eigen::Matrix3d Ja_t_omega = l.d_from.transpose() * omega;
  const Eigen::Matrix3d Jb_t_omega = l.d_to.transpose() * omega;
  // The same blocks, and in the same order, as the triplets these sums
  // replaced: (a, a), the one below the diagonal, (b, b).
  if (c.a >= 0) add_diagonal(c.a, Ja_t_omega * l.d_from);
  if (c.a >= 0 && c.b >= 0) {
    if (c.a > c.b)
      add_below(c.b, c.below, Ja_t_omega * l.d_to);
    else
      add_below(c.a, c.below, Jb_t_omega * l.d_from);
  }
  if (c.b >= 0) add_diagonal(c.b, Jb_t_omega * l.d_to);
  if (c.a >= 0) g_.segment<3>(c.a) += Ja_t_omega * l.residual;
  if (c.b >= 0) g_.segment<3>(c.b) += Jb_t_omega * l.residual;
}

}  // namespace hmt::global_map

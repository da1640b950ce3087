#include "hmt/area/ncut.h"

#include <cmath>
#include <stdexcept>

namespace hmt::area {

CutValues cut_values(const WeightMatrix& W, const std::vector<char>& in_a) {
  if (static_cast<Eigen::Index>(in_a.size()) != W.cols() ||
      W.rows() != W.cols())
    throw std::invalid_argument("cut_values: size mismatch");
  CutValues v;
  for (Eigen::Index j = 0; j < W.outerSize(); ++j) {
    for (WeightMatrix::InnerIterator it(W, j); it; ++it) {
      const Eigen::Index i = it.row();
      if (i == j) continue;
      const double w = it.value();
      if (in_a[j])
        v.assoc_a += w;
      else
        v.assoc_b += w;
      if (in_a[i] && !in_a[j]) v.cut += w;  // each A-B pair once
    }
  }
  return v;
}

double normalized_cut(const WeightMatrix& W, const std::vector<char>& in_a) {
  return cut_values(W, in_a).ncut();
}

Eigen::VectorXd degrees(const WeightMatrix& W) {
  Eigen::VectorXd d = Eigen::VectorXd::Zero(W.cols());
  for (Eigen::Index j = 0; j < W.outerSize(); ++j)
    for (WeightMatrix::InnerIterator it(W, j); it; ++it)
      if (it.row() != j) d[j] += it.value();
  return d;
}

std::vector<int> connected_components(const WeightMatrix& W, int* count) {
  const int n = static_cast<int>(W.cols());
  std::vector<int> label(n, -1);
  std::vector<int> stack;
  int c = 0;
  for (int s = 0; s < n; ++s) {
    if (label[s] >= 0) continue;
    label[s] = c;
    stack.assign(1, s);
    while (!stack.empty()) {
      const int j = stack.back();
      stack.pop_back();
      for (WeightMatrix::InnerIterator it(W, j); it; ++it) {
        const int i = static_cast<int>(it.row());
        if (i == j || !(it.value() > 0.0) || label[i] >= 0) continue;
        label[i] = c;
        stack.push_back(i);
      }
    }
    ++c;
  }
  if (count) *count = c;
  return label;
}

WeightMatrix submatrix(const WeightMatrix& W, const std::vector<int>& nodes) {
  std::vector<int> local(W.cols(), -1);
  for (size_t k = 0; k < nodes.size(); ++k)
    local[nodes[k]] = static_cast<int>(k);
  std::vector<Eigen::Triplet<double>> t;
  for (size_t k = 0; k < nodes.size(); ++k) {
    for (WeightMatrix::InnerIterator it(W, nodes[k]); it; ++it) {
      const int i = local[it.row()];
      if (i < 0 || i == static_cast<int>(k)) continue;
      t.emplace_back(i, static_cast<int>(k), it.value());
    }
  }
  WeightMatrix S(nodes.size(), nodes.size());
  S.setFromTriplets(t.begin(), t.end());
  return S;
}

void check_weight_matrix(const WeightMatrix& W) {
  if (W.rows() != W.cols())
    throw std::invalid_argument("weight matrix is not square");
  for (Eigen::Index j = 0; j < W.outerSize(); ++j) {
    for (WeightMatrix::InnerIterator it(W, j); it; ++it) {
      const double w = it.value();
      if (!std::isfinite(w) || w < 0.0)
        throw std::invalid_argument(
            "weight matrix has a negative or non-finite weight");
      const double wt = W.coeff(j, it.row());
      if (std::fabs(w - wt) > 1e-9 * std::max(std::fabs(w), std::fabs(wt)))
        throw std::invalid_argument("weight matrix is not symmetric");
    }
  }
}

}  // namespace hmt::area

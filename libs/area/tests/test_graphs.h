// Random and structured weight matrices for the partition tests.
#pragma once

#include <Eigen/SparseCore>
#include <vector>

#include "hmt/area/ncut.h"
#include "hmt/common/random.h"

namespace hmt::area::testing {

inline WeightMatrix from_triplets(
    int n, const std::vector<Eigen::Triplet<double>>& t) {
  std::vector<Eigen::Triplet<double>> sym;
  for (const auto& e : t) {
    sym.push_back(e);
    sym.emplace_back(e.col(), e.row(), e.value());
  }
  WeightMatrix W(n, n);
  W.setFromTriplets(sym.begin(), sym.end());
  return W;
}

// Connected random graph: a random spanning tree plus each other pair with
// probability p; weights uniform in (0.05, 1].
inline WeightMatrix random_connected(int n, double p, Random& rng) {
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 1; i < n; ++i) {
    const int j = static_cast<int>(rng.uniform() * i);
    t.emplace_back(i, j, rng.uniform(0.05, 1.0));
  }
  for (int i = 0; i < n; ++i)
    for (int j = i + 2; j < n; ++j)
      if (rng.uniform() < p) t.emplace_back(i, j, rng.uniform(0.05, 1.0));
  return from_triplets(n, t);  // duplicates (tree + extra) are summed
}

// Random graph that may be disconnected and may have isolated nodes.
inline WeightMatrix random_graph(int n, double p, Random& rng) {
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      if (rng.uniform() < p) t.emplace_back(i, j, rng.uniform(0.0, 1.0));
  return from_triplets(n, t);
}

// Dense blocks of the given sizes (complete, intra weights uniform in
// [lo, hi]), consecutive blocks joined by `bridges` edges of weight `weak`.
// A complete block of m equal weights has Ncut m/(m-1) > 1 for every split,
// so with weights close together it is one area at tau = 1.
inline WeightMatrix blocks(const std::vector<int>& sizes, double weak,
                           int bridges, Random& rng, double lo = 0.9,
                           double hi = 1.0) {
  std::vector<Eigen::Triplet<double>> t;
  std::vector<int> start;
  int n = 0;
  for (int s : sizes) {
    start.push_back(n);
    for (int i = 0; i < s; ++i)
      for (int j = i + 1; j < s; ++j)
        t.emplace_back(n + i, n + j, rng.uniform(lo, hi));
    n += s;
  }
  for (size_t b = 0; b + 1 < sizes.size(); ++b)
    for (int k = 0; k < bridges; ++k)
      t.emplace_back(start[b] + k % sizes[b],
                     start[b + 1] + (k * 7) % sizes[b + 1], weak);
  return from_triplets(n, t);
}

}  // namespace hmt::area::testing

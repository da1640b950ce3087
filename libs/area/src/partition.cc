#include "hmt/area/partition.h"

#include <algorithm>
#include <numeric>
#include <stdexcept>

#include "hmt/area/spectral_bisection.h"

namespace hmt::area {

PartitionResult recursive_partition(const WeightMatrix& W,
                                    const PartitionOptions& options) {
  check_weight_matrix(W);
  PartitionResult out;
  const int n = static_cast<int>(W.cols());
  if (n == 0) return out;
  const BisectionOptions bopt{options.split_method, options.min_cluster_size};
  const size_t min_size = static_cast<size_t>(options.min_cluster_size);

  // Depth-first on an explicit stack (a chain of unbalanced splits could be
  // as deep as n). Each entry is a sorted list of node indices into W.
  std::vector<std::vector<int>> pending(1);
  pending[0].resize(n);
  std::iota(pending[0].begin(), pending[0].end(), 0);
  while (!pending.empty()) {
    std::vector<int> nodes = std::move(pending.back());
    pending.pop_back();
    const bool whole = static_cast<int>(nodes.size()) == n;
    const Bisection b = whole ? spectral_bisection(W, bopt)
                              : spectral_bisection(submatrix(W, nodes), bopt);
    if (b.valid && b.ncut < options.tau && b.a.size() >= min_size &&
        b.b.size() >= min_size) {
      out.accepted_ncuts.push_back(b.ncut);
      std::vector<int> a, c;
      for (int i : b.a) a.push_back(nodes[i]);
      for (int i : b.b) c.push_back(nodes[i]);
      pending.push_back(std::move(c));
      pending.push_back(std::move(a));
    } else {
      out.groups.push_back(std::move(nodes));
    }
  }
  std::sort(out.groups.begin(), out.groups.end(),
            [](const auto& x, const auto& y) { return x.front() < y.front(); });
  return out;
}

std::vector<int> group_labels(const std::vector<std::vector<int>>& groups,
                              int n) {
  std::vector<int> label(n, -1);
  for (size_t g = 0; g < groups.size(); ++g)
    for (int i : groups[g]) {
      if (i < 0 || i >= n || label[i] >= 0)
        throw std::invalid_argument("group_labels: not a partition of 0..n-1");
      label[i] = static_cast<int>(g);
    }
  for (int l : label)
    if (l < 0) throw std::invalid_argument("group_labels: a node has no group");
  return label;
}

}  // namespace hmt::area

// Recursive k-way partition by spectral bisection (000 Table 1):
//
//   RecursivePart(G):  ({A, B}, Ncut) = SpectralBisection(G)
//                      if Ncut < tau: RecursivePart(A), RecursivePart(B)
//                      else:          G is one group
//
// with the extra rule that a bisection leaving fewer than min_cluster_size
// nodes on a side is not accepted. tau = 1 is the parameter-free threshold of
// 001 Eq. 12-13 (the cut equal to the geometric mean of the two internal
// associations gives Ncut = 1).
#pragma once

#include <vector>

#include "hmt/area/area_options.h"
#include "hmt/area/ncut.h"

namespace hmt::area {

struct PartitionResult {
  // Groups of node indices, each sorted ascending, ordered by their smallest
  // index. Every node is in exactly one group.
  std::vector<std::vector<int>> groups;
  // Ncut of every accepted bisection, in the order they were made.
  std::vector<double> accepted_ncuts;
};

// Throws std::invalid_argument if W is not a valid weight matrix (see
// check_weight_matrix). An empty W gives no groups.
PartitionResult recursive_partition(const WeightMatrix& W,
                                    const PartitionOptions& options);

// group index of every node, from a list of groups over nodes 0..n-1.
std::vector<int> group_labels(const std::vector<std::vector<int>>& groups,
                              int n);

}  // namespace hmt::area

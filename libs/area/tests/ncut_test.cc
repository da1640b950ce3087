#include "hmt/area/ncut.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "test_graphs.h"

namespace hmt::area {
namespace {

using testing::from_triplets;

TEST(area_Ncut, HandComputedExample) {
  // 0-1 (3), 1-2 (1), 2-3 (2); split {0,1} | {2,3}:
  // cut = 1, assoc(A) = 3+3+1 = 7, assoc(B) = 1+2+2 = 5.
  const WeightMatrix W =
      from_triplets(4, {{0, 1, 3.0}, {1, 2, 1.0}, {2, 3, 2.0}});
  const CutValues v = cut_values(W, {1, 1, 0, 0});
  EXPECT_DOUBLE_EQ(v.cut, 1.0);
  EXPECT_DOUBLE_EQ(v.assoc_a, 7.0);
  EXPECT_DOUBLE_EQ(v.assoc_b, 5.0);
  EXPECT_DOUBLE_EQ(v.ncut(), 1.0 / 7.0 + 1.0 / 5.0);
  // Same split with the labels swapped.
  EXPECT_DOUBLE_EQ(normalized_cut(W, {0, 0, 1, 1}), v.ncut());
}

TEST(area_Ncut, DiagonalIsIgnored) {
  WeightMatrix W = from_triplets(3, {{0, 1, 1.0}, {1, 2, 1.0}});
  const double before = normalized_cut(W, {1, 0, 0});
  W.coeffRef(0, 0) = 5.0;
  W.coeffRef(2, 2) = 7.0;
  EXPECT_DOUBLE_EQ(normalized_cut(W, {1, 0, 0}), before);
  EXPECT_DOUBLE_EQ(degrees(W)[0], 1.0);
}

TEST(area_Ncut, WorstSplitIsTwoAndSeparatedSplitIsZero) {
  // Bipartite graph split along its two sides: every edge is cut.
  const WeightMatrix W =
      from_triplets(4, {{0, 2, 1.0}, {0, 3, 0.5}, {1, 2, 2.0}, {1, 3, 1.0}});
  EXPECT_DOUBLE_EQ(normalized_cut(W, {1, 1, 0, 0}), 2.0);
  // Two components, and a group of isolated nodes.
  const WeightMatrix V = from_triplets(5, {{0, 1, 1.0}, {2, 3, 1.0}});
  EXPECT_DOUBLE_EQ(normalized_cut(V, {1, 1, 0, 0, 0}), 0.0);
  EXPECT_DOUBLE_EQ(normalized_cut(V, {0, 0, 0, 0, 1}), 0.0);
}

TEST(area_Ncut, AlwaysInZeroTwoOnRandomGraphsAndSplits) {
  Random rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 2 + static_cast<int>(rng.uniform() * 40);
    const WeightMatrix W =
        testing::random_graph(n, rng.uniform(0.05, 0.9), rng);
    std::vector<char> in_a(n);
    for (auto& x : in_a) x = rng.uniform() < 0.5;
    const double nc = normalized_cut(W, in_a);
    EXPECT_GE(nc, 0.0);
    EXPECT_LE(nc, 2.0 + 1e-12);
  }
}

TEST(area_Ncut, ConnectedComponentsAreLabelledBySmallestNode) {
  const WeightMatrix W =
      from_triplets(6, {{4, 5, 1.0}, {1, 3, 1.0}, {3, 0, 0.5}});
  int count = 0;
  const std::vector<int> c = connected_components(W, &count);
  EXPECT_EQ(count, 3);
  EXPECT_EQ(c, (std::vector<int>{0, 0, 1, 0, 2, 2}));
}

TEST(area_Ncut, SubmatrixKeepsInducedEdgesInOrder) {
  const WeightMatrix W =
      from_triplets(4, {{0, 1, 1.0}, {1, 2, 2.0}, {2, 3, 3.0}, {0, 3, 4.0}});
  const WeightMatrix S = submatrix(W, {3, 1, 0});
  EXPECT_DOUBLE_EQ(S.coeff(0, 2), 4.0);  // 3-0
  EXPECT_DOUBLE_EQ(S.coeff(1, 2), 1.0);  // 1-0
  EXPECT_DOUBLE_EQ(S.coeff(0, 1), 0.0);  // 3-1: no edge
  EXPECT_EQ(S.nonZeros(), 4);
}

TEST(area_Ncut, WeightMatrixChecks) {
  WeightMatrix W = from_triplets(3, {{0, 1, 1.0}});
  EXPECT_NO_THROW(check_weight_matrix(W));
  W.coeffRef(1, 2) = 0.5;  // one triangle only
  EXPECT_THROW(check_weight_matrix(W), std::invalid_argument);
  WeightMatrix N = from_triplets(3, {{0, 1, -1.0}});
  EXPECT_THROW(check_weight_matrix(N), std::invalid_argument);
  EXPECT_THROW(cut_values(W, {1, 0}), std::invalid_argument);
}

}  // namespace
}  // namespace hmt::area

#include "hmt/area/partition.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

#include "test_graphs.h"

namespace hmt::area {
namespace {

std::vector<int> range(int a, int b) {
  std::vector<int> v(b - a);
  std::iota(v.begin(), v.end(), a);
  return v;
}

TEST(area_RecursivePartition, ThreeWeaklyJoinedBlocksGiveExactlyThreeGroups) {
  Random rng(21);
  for (SplitMethod m :
       {SplitMethod::kMean, SplitMethod::kSign, SplitMethod::kSweep}) {
    const WeightMatrix W = testing::blocks({15, 22, 18}, 0.02, 3, rng);
    PartitionOptions o;
    o.tau = 1.0;
    o.split_method = m;
    const PartitionResult r = recursive_partition(W, o);
    ASSERT_EQ(r.groups.size(), 3u) << to_string(m);
    EXPECT_EQ(r.groups[0], range(0, 15));
    EXPECT_EQ(r.groups[1], range(15, 37));
    EXPECT_EQ(r.groups[2], range(37, 55));
    ASSERT_EQ(r.accepted_ncuts.size(), 2u);
    for (double nc : r.accepted_ncuts) EXPECT_LT(nc, 0.05);
  }
}

TEST(area_RecursivePartition, ATinyThresholdKeepsWeaklyJoinedBlocksTogether) {
  Random rng(21);
  const WeightMatrix W = testing::blocks({15, 22, 18}, 0.02, 3, rng);
  PartitionOptions o;
  o.tau = 1e-4;
  const PartitionResult r = recursive_partition(W, o);
  ASSERT_EQ(r.groups.size(), 1u);
  EXPECT_EQ(r.groups[0], range(0, 55));
  o.tau = 0.0;  // never splits
  EXPECT_EQ(recursive_partition(W, o).groups.size(), 1u);
}

TEST(area_RecursivePartition, ADenseBlockIsNotSplitWithTauOne) {
  Random rng(4);
  const WeightMatrix W = testing::blocks({40}, 0.0, 0, rng);
  EXPECT_EQ(recursive_partition(W, PartitionOptions{}).groups.size(), 1u);
}

TEST(area_RecursivePartition, MinimumClusterSizeStopsSmallGroups) {
  Random rng(8);
  const WeightMatrix W = testing::blocks({20, 3, 20}, 0.01, 2, rng);
  PartitionOptions o;
  EXPECT_EQ(recursive_partition(W, o).groups.size(), 3u);
  o.min_cluster_size = 4;
  const PartitionResult r = recursive_partition(W, o);
  for (const auto& g : r.groups) EXPECT_GE(g.size(), 4u);
  EXPECT_EQ(r.groups.size(), 2u);
}

TEST(area_RecursivePartition, DisconnectedPiecesAndIsolatedNodesBecomeGroups) {
  const WeightMatrix W = testing::from_triplets(7, {{0, 2, 1.0},
                                                    {2, 4, 1.0},
                                                    {0, 4, 1.0},
                                                    {1, 3, 1.0},
                                                    {3, 5, 1.0},
                                                    {1, 5, 1.0}});
  const PartitionResult r = recursive_partition(W, PartitionOptions{});
  ASSERT_EQ(r.groups.size(), 3u);
  EXPECT_EQ(r.groups[0], (std::vector<int>{0, 2, 4}));
  EXPECT_EQ(r.groups[1], (std::vector<int>{1, 3, 5}));
  EXPECT_EQ(r.groups[2], (std::vector<int>{6}));
}

TEST(area_RecursivePartition, OutputIsAPartitionSortedAndDeterministic) {
  Random rng(13);
  for (int trial = 0; trial < 15; ++trial) {
    const int n = 5 + static_cast<int>(rng.uniform() * 80);
    const WeightMatrix W =
        testing::random_graph(n, rng.uniform(0.03, 0.3), rng);
    PartitionOptions o;
    o.tau = rng.uniform(0.2, 1.5);
    const PartitionResult r = recursive_partition(W, o);
    EXPECT_NO_THROW(group_labels(r.groups, n));
    for (size_t g = 0; g < r.groups.size(); ++g) {
      EXPECT_TRUE(std::is_sorted(r.groups[g].begin(), r.groups[g].end()));
      if (g > 0) {
        EXPECT_LT(r.groups[g - 1].front(), r.groups[g].front());
      }
    }
    for (double nc : r.accepted_ncuts) EXPECT_LT(nc, o.tau);
    const PartitionResult again = recursive_partition(W, o);
    EXPECT_EQ(again.groups, r.groups);
  }
}

TEST(area_RecursivePartition, RejectsInvalidWeightMatrices) {
  WeightMatrix W(3, 3);
  W.coeffRef(0, 1) = 1.0;
  EXPECT_THROW(recursive_partition(W, PartitionOptions{}),
               std::invalid_argument);
  EXPECT_TRUE(recursive_partition(WeightMatrix(0, 0), PartitionOptions{})
                  .groups.empty());
}

}  // namespace
}  // namespace hmt::area

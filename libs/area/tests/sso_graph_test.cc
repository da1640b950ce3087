#include "hmt/area/sso_graph.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <numeric>
#include <utility>

#include "hmt/area/offline_grouping.h"
#include "sim_world.h"

namespace hmt::area {
namespace {

std::vector<Keyframe> every_kth(const std::vector<Keyframe>& all, size_t k) {
  std::vector<Keyframe> out;
  for (size_t i = 0; i < all.size(); i += k) out.push_back(all[i]);
  return out;
}

// Every stored weight equals the pairwise SSO, and every pair with SSO >=
// min_sso is stored: the spatial indexes lose nothing.
void expect_graph_matches_pairwise(const std::vector<Keyframe>& kfs, const AreaOptions& o,
                                   std::shared_ptr<WorkerPool> pool = nullptr) {
  SsoGraph g(o, std::move(pool));
  for (size_t i = 0; i < kfs.size(); ++i) g.add(static_cast<int>(i), kfs[i]);
  std::vector<PreparedScan> scans;
  for (const auto& k : kfs) scans.emplace_back(k.scan, o.sso);
  size_t stored = 0;
  for (size_t i = 0; i < kfs.size(); ++i) {
    for (size_t j = i + 1; j < kfs.size(); ++j) {
      const double expected =
          scan_sso(scans[i], kfs[i].pose, scans[j], kfs[j].pose, o.sso);
      const double w = g.weight(static_cast<int>(i), static_cast<int>(j));
      EXPECT_DOUBLE_EQ(w, g.weight(static_cast<int>(j), static_cast<int>(i)));
      if (expected >= o.min_sso && expected > 0.0) {
        EXPECT_NEAR(w, expected, 1e-12) << i << " " << j;
        ++stored;
      } else {
        EXPECT_EQ(w, 0.0) << i << " " << j;
      }
    }
  }
  EXPECT_EQ(g.num_edges(), stored);
  EXPECT_GT(stored, kfs.size());  // the scenes do overlap
}

TEST(area_SsoGraph, FixedDeltaWeightsEqualPairwiseSso) {
  AreaOptions o;
  expect_graph_matches_pairwise(every_kth(sim::three_rooms_walk(), 3), o);
}

TEST(area_SsoGraph, ProbabilisticWeightsEqualPairwiseSso) {
  AreaOptions o;
  o.sso.use_probabilistic = true;
  o.sso.range_std = 0.02;
  o.index_cell_size = 3.0;
  auto kfs = every_kth(sim::three_rooms_walk(), 6);
  for (size_t i = 0; i < kfs.size(); ++i) {
    kfs[i].pose.cov.diagonal() << 0.003, 0.002, 1e-4;
    // Poses off their true value by about one sigma.
    kfs[i].pose.mean =
        kfs[i].pose.mean + Pose2D(0.05 * ((i % 3) - 1.0), 0.04, 0.0);
  }
  expect_graph_matches_pairwise(kfs, o);
  // The pairs evaluated on a pool (3 threads) join into the same graph.
  expect_graph_matches_pairwise(kfs, o, std::make_shared<WorkerPool>(3));
}

TEST(area_SsoGraph, RemovingKeyframesRemovesTheirEdges) {
  AreaOptions o;
  const auto kfs = every_kth(sim::three_rooms_walk(), 4);
  SsoGraph full(o), g(o);
  for (size_t i = 0; i < kfs.size(); ++i) {
    full.add(static_cast<int>(i), kfs[i]);
    g.add(static_cast<int>(i), kfs[i]);
  }
  const size_t edges = g.num_edges();
  const auto removed_edges = g.edges(5).size();
  g.remove(5);
  EXPECT_FALSE(g.contains(5));
  EXPECT_EQ(g.num_edges(), edges - removed_edges);
  for (int i = 0; i < static_cast<int>(kfs.size()); ++i) {
    if (i == 5) continue;
    EXPECT_EQ(g.weight(i, 5), 0.0);
    for (int j = 0; j < static_cast<int>(kfs.size()); ++j)
      if (j != 5 && j != i) {
        EXPECT_EQ(g.weight(i, j), full.weight(i, j));
      }
  }
  // Re-adding under a new id restores the same weights.
  g.add(1000, kfs[5]);
  for (int i = 0; i < static_cast<int>(kfs.size()); ++i) {
    if (i != 5) {
      EXPECT_DOUBLE_EQ(g.weight(i, 1000), full.weight(i, 5));
    }
  }
  EXPECT_THROW(g.add(1000, kfs[5]), std::invalid_argument);
  EXPECT_THROW(g.remove(5), std::invalid_argument);
  const auto ids = g.ids();
  EXPECT_TRUE(std::is_sorted(ids.begin(), ids.end()));
  EXPECT_EQ(ids.back(), 1000);
}

TEST(area_SsoGraph, WeightMatrixIsSymmetricSparseAndFollowsTheIdOrder) {
  AreaOptions o;
  const auto kfs = every_kth(sim::three_rooms_walk(), 5);
  SsoGraph g(o);
  for (size_t i = 0; i < kfs.size(); ++i) g.add(static_cast<int>(i), kfs[i]);
  const std::vector<int> ids = {7, 2, 11, 0, 5};
  const WeightMatrix W = g.weight_matrix(ids);
  EXPECT_NO_THROW(check_weight_matrix(W));
  for (size_t a = 0; a < ids.size(); ++a) {
    EXPECT_EQ(W.coeff(a, a), 0.0);
    for (size_t b = 0; b < ids.size(); ++b)
      if (a != b) {
        EXPECT_DOUBLE_EQ(W.coeff(a, b), g.weight(ids[a], ids[b]));
      }
  }
  EXPECT_THROW(g.weight_matrix({1, 1}), std::invalid_argument);
  EXPECT_THROW(g.weight_matrix({999}), std::invalid_argument);
  // The offline helper builds the same matrix over all keyframes.
  std::vector<int> all(kfs.size());
  std::iota(all.begin(), all.end(), 0);
  const WeightMatrix F = sso_weight_matrix(kfs, o);
  EXPECT_EQ((Eigen::MatrixXd(F) - Eigen::MatrixXd(g.weight_matrix(all))).norm(),
            0.0);
}

TEST(area_SsoGraph, WorkPerKeyframeDoesNotGrowWithTheGraph) {
  // 100 m of corridor: the keyframes matched against each new one are those
  // within sensor range, not all those stored.
  const auto kfs = sim::corridor_walk(100.0, 0.5);
  for (bool prob : {false, true}) {
    AreaOptions o;
    o.sso.use_probabilistic = prob;
    SsoGraph g(o);
    size_t at_60 = 0, max_late = 0;
    for (size_t i = 0; i < kfs.size(); ++i) {
      g.add(static_cast<int>(i), kfs[i]);
      if (i == 60) at_60 = g.last_candidates();
      if (i > 140) max_late = std::max(max_late, g.last_candidates());
    }
    EXPECT_GT(at_60, 10u) << prob;
    EXPECT_LE(max_late, at_60 + at_60 / 2) << prob;
    EXPECT_LT(max_late, 100u) << prob;
  }
}

}  // namespace
}  // namespace hmt::area

#include "hmt/grouping/topology.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace hmt::grouping {
namespace {

area::WeightMatrix matrix(int n, const std::vector<std::tuple<int, int, double>>& edges) {
  std::vector<Eigen::Triplet<double>> t;
  for (const auto& [a, b, w] : edges) {
    t.emplace_back(a, b, w);
    t.emplace_back(b, a, w);
  }
  area::WeightMatrix W(n, n);
  W.setFromTriplets(t.begin(), t.end());
  return W;
}

TEST(Topology, AverageIsCircularInTheAngle) {
  const PoseSample s = average_poses(
      {Pose2D(1, 0, M_PI - 0.1), Pose2D(3, 2, -M_PI + 0.1)});
  EXPECT_NEAR(s.mean.x, 2.0, 1e-12);
  EXPECT_NEAR(s.mean.y, 1.0, 1e-12);
  EXPECT_NEAR(std::fabs(s.mean.theta), M_PI, 1e-12);
  ASSERT_TRUE(s.has_cov);
  // Deviations (-1, -1, -0.1) and (1, 1, 0.1) up to the sign of theta's.
  EXPECT_NEAR(s.cov(0, 0), 2.0, 1e-12);
  EXPECT_NEAR(s.cov(0, 1), 2.0, 1e-12);
  EXPECT_NEAR(s.cov(2, 2), 0.02, 1e-12);
  EXPECT_NEAR(std::fabs(s.cov(0, 2)), 0.2, 1e-12);
  const PoseSample one = average_poses({Pose2D(1, 2, 3)});
  EXPECT_FALSE(one.has_cov);
  EXPECT_EQ(one.n, 1u);
  EXPECT_THROW(average_poses({}), std::invalid_argument);
}

// Four keyframes along x, two groups {0,1} and {2,3}; group 1's frame is
// keyframe 2's pose.
TEST(Topology, ExactLocalPosesGiveTheRelativePoseOfTheReferenceFrames) {
  const std::vector<Pose2D> global = {Pose2D(0, 0, 0), Pose2D(1, 0, 0.1),
                                      Pose2D(2, 1, 0.5), Pose2D(3, 1, 0.7)};
  const std::vector<int> label = {0, 0, 1, 1};
  std::vector<Pose2D> local(4);
  for (int k = 0; k < 4; ++k) local[k] = global[k] - global[label[k] == 0 ? 0 : 2];
  const auto W = matrix(4, {{0, 1, 0.8}, {1, 2, 0.3}, {0, 3, 0.1}, {2, 3, 0.9}});
  const auto arcs = build_topology(global, local, label, W);
  ASSERT_EQ(arcs.size(), 1u);
  const TopologyArc& a = arcs[0];
  EXPECT_EQ(a.from, 0);
  EXPECT_EQ(a.to, 1);
  EXPECT_EQ(a.route_pairs, 1u);    // (1, 2)
  EXPECT_EQ(a.overlap_pairs, 2u);  // (1, 2) and (0, 3)
  EXPECT_EQ(a.transform.n, 2u);    // two distinct pairs
  EXPECT_NEAR(a.sso_cut, 0.4, 1e-12);
  const Pose2D expect = global[2] - global[0];
  EXPECT_NEAR(a.transform.mean.x, expect.x, 1e-12);
  EXPECT_NEAR(a.transform.mean.y, expect.y, 1e-12);
  EXPECT_NEAR(a.transform.mean.theta, expect.theta, 1e-12);
  EXPECT_NEAR(a.transform.cov.norm(), 0.0, 1e-20);
}

TEST(Topology, RefinedLocalPosesSpreadTheSamples) {
  const std::vector<Pose2D> global = {Pose2D(0, 0, 0), Pose2D(1, 0, 0),
                                      Pose2D(2, 0, 0), Pose2D(3, 0, 0)};
  const std::vector<int> label = {0, 0, 1, 1};
  std::vector<Pose2D> local = {Pose2D(0, 0, 0), Pose2D(1.1, 0, 0),
                               Pose2D(0, 0, 0), Pose2D(1, 0, 0)};
  const auto W = matrix(4, {{0, 2, 0.5}});
  const auto arcs = build_topology(global, local, label, W);
  ASSERT_EQ(arcs.size(), 1u);
  // Pair (1, 2): 1.1 + 1 = 2.1; pair (0, 2): 0 + 2 = 2.
  EXPECT_NEAR(arcs[0].transform.mean.x, 2.05, 1e-12);
  EXPECT_NEAR(arcs[0].transform.cov(0, 0), 0.005, 1e-12);
  EXPECT_EQ(arcs[0].route_pairs, 1u);
  EXPECT_EQ(arcs[0].overlap_pairs, 1u);
}

TEST(Topology, ArcsAreOrderedFromLowerToHigherGroup) {
  // Route 0 -> 1 -> 0 -> 2: groups {0, 2}, {1}, {3}.
  const std::vector<Pose2D> global(4);
  const std::vector<int> label = {0, 1, 0, 2};
  const auto arcs = build_topology(global, global, label, matrix(4, {}));
  ASSERT_EQ(arcs.size(), 2u);
  EXPECT_EQ(arcs[0].from, 0);
  EXPECT_EQ(arcs[0].to, 1);
  EXPECT_EQ(arcs[0].route_pairs, 2u);  // (0, 1) and (2, 1)
  EXPECT_EQ(arcs[1].from, 0);
  EXPECT_EQ(arcs[1].to, 2);
  const std::string dot = topology_dot({{0, 2, 0, Pose2D(), "group_000.png"},
                                        {1, 1, 1, Pose2D(1, 2, 0), "group_001.png"},
                                        {2, 1, 3, Pose2D(), "group_002.png"}},
                                       arcs);
  EXPECT_NE(dot.find("digraph topology {"), std::string::npos);
  EXPECT_NE(dot.find("g0 -> g1"), std::string::npos);
  EXPECT_NE(dot.find("g0 -> g2"), std::string::npos);
  EXPECT_NE(dot.find("pos=\"72.0,144.0\""), std::string::npos);
}

}  // namespace
}  // namespace hmt::grouping

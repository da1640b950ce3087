#include "hmt/topology/shortest_paths.h"

#include <gtest/gtest.h>

#include "test_util.h"

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace hmt::topology {
namespace {

using testing_util::cov_of;
using testing_util::diag;
using testing_util::vec;




HmtMap areas(int n) {
  HmtMap m;
  for (int i = 0; i < n; ++i) m.add_area(static_cast<AreaId>(i));
  return m;
}

TEST(ShortestPaths, ChainCompositionMatchesMonteCarlo) {
  // Eq. 15 along 0 -> 1 -> 2 -> 3 -> 4, with arcs given in both directions
  // (the 3-2 arc is stored from 2, queried backwards by the path).
  HmtMap m = areas(5);
  const std::vector<PoseGaussian> arcs = {
      PoseGaussian(Pose2D(2.0, 0.0, 0.3),
                   cov_of(0.05, 0.08, 0.03, 0.3, 0.2, -0.1)),
      PoseGaussian(Pose2D(1.5, 0.5, -0.2),
                   cov_of(0.08, 0.05, 0.04, -0.2, 0.1, 0.3)),
      PoseGaussian(Pose2D(2.0, -0.3, 0.5),
                   cov_of(0.06, 0.06, 0.05, 0.1, -0.3, 0.2)),
      PoseGaussian(Pose2D(1.0, 1.0, 0.1),
                   cov_of(0.07, 0.04, 0.03, 0.0, 0.2, 0.1))};
  m.add_arc_measurement(0, 1, arcs[0]);
  m.add_arc_measurement(1, 2, arcs[1]);
  m.add_arc_measurement(3, 2, inverse(arcs[2]));
  m.add_arc_measurement(3, 4, arcs[3]);
  const PoseGaussian g = compose_path(m, {0, 1, 2, 3, 4});

  Random rng(2024);
  const int n = 20000;
  std::vector<Eigen::Vector3d> d;
  d.reserve(n);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    Pose2D p;
    for (const PoseGaussian& a : arcs) p = p + sample(a, rng);
    d.push_back(difference(p, g.mean));
    mean += d.back();
  }
  mean /= n;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& x : d) cov += (x - mean) * (x - mean).transpose();
  cov /= n - 1;

  // The linearised Gaussian is not a loose bound: the heading uncertainty
  // builds a position spread of tens of centimetres through the lever arms.
  EXPECT_GT(std::sqrt(g.cov(1, 1)), 0.15);
  for (int i = 0; i < 3; ++i)
    EXPECT_LT(std::abs(mean(i)), 0.1 * std::sqrt(g.cov(i, i))) << "mean " << i;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      EXPECT_NEAR(cov(i, j), g.cov(i, j),
                  0.05 * std::sqrt(g.cov(i, i) * g.cov(j, j)))
          << "cov(" << i << "," << j << ")";

  // The tree reaches 4 along the chain with the same Gaussian.
  const PathTree tree = shortest_paths(m, 0);
  EXPECT_EQ(tree.path_to(4), (std::vector<AreaId>{0, 1, 2, 3, 4}));
  EXPECT_LT((vec(tree.pose_of(4).mean) - vec(g.mean)).cwiseAbs().maxCoeff(),
            1e-12);
  EXPECT_LT((tree.pose_of(4).cov - g.cov).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(ShortestPaths, ReversedPathGivesTheInverseGaussian) {
  HmtMap m = areas(4);
  m.add_arc_measurement(0, 1,
                        PoseGaussian(Pose2D(2, 0, 0.4), diag(0.1, 0.2, 0.05)));
  m.add_arc_measurement(2, 1,
                        PoseGaussian(Pose2D(1, 1, -0.7), diag(0.2, 0.1, 0.03)));
  m.add_arc_measurement(2, 3,
                        PoseGaussian(Pose2D(-1, 2, 2.5), diag(0.3, 0.1, 0.02)));
  const PoseGaussian there = compose_path(m, {0, 1, 2, 3});
  const PoseGaussian back = compose_path(m, {3, 2, 1, 0});
  const PoseGaussian inv = inverse(there);
  EXPECT_LT((vec(back.mean) - vec(inv.mean)).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((back.cov - inv.cov).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_THROW(compose_path(m, {0, 2}), std::out_of_range);
  EXPECT_THROW(compose_path(m, {}), std::invalid_argument);
  const PoseGaussian self = compose_path(m, {2});
  EXPECT_EQ(self.cov, Eigen::Matrix3d::Zero());
}

TEST(ShortestPaths, DijkstraPicksTheMoreCertainRoute) {
  // 0 -> 3 directly (one uncertain arc) or 0 -> 1 -> 2 -> 3 (three certain
  // arcs): "shortest" is "most certain", so the long way round wins.
  HmtMap m = areas(5);
  m.add_arc_measurement(0, 3,
                        PoseGaussian(Pose2D(6, 0, 0), diag(1.0, 1.0, 0.2)));
  m.add_arc_measurement(0, 1,
                        PoseGaussian(Pose2D(2, 0, 0), diag(0.1, 0.1, 0.02)));
  m.add_arc_measurement(1, 2,
                        PoseGaussian(Pose2D(2, 0, 0), diag(0.1, 0.1, 0.02)));
  m.add_arc_measurement(2, 3,
                        PoseGaussian(Pose2D(2, 0.1, 0), diag(0.1, 0.1, 0.02)));
  PathTree tree = shortest_paths(m, 0);
  EXPECT_EQ(tree.path_to(3), (std::vector<AreaId>{0, 1, 2, 3}));
  EXPECT_EQ(tree.nodes.at(3).hops, 3u);
  EXPECT_EQ(tree.nodes.at(3).parent, 2u);
  // The cost is that of the composed Gaussian, lever arms included (about
  // 0.069 here against the direct arc's 2.04).
  EXPECT_NEAR(tree.nodes.at(3).cost, path_cost(tree.pose_of(3).cov), 1e-15);
  EXPECT_GT(tree.nodes.at(3).cost, 3 * (0.01 + 0.01 + 0.0004));
  EXPECT_LT(tree.nodes.at(3).cost, 1.0 + 1.0 + 0.04);
  EXPECT_NEAR(tree.pose_of(3).mean.y, 0.1, 1e-12);  // the chain's mean, not 0
  // Area 4 has no arc: not reached.
  EXPECT_FALSE(tree.reaches(4));
  EXPECT_THROW(tree.path_to(4), std::out_of_range);
  // The root is exactly known.
  EXPECT_EQ(tree.pose_of(0).cov, Eigen::Matrix3d::Zero());
  EXPECT_EQ(tree.path_to(0), (std::vector<AreaId>{0}));

  // Crossing 0-3 many more times makes the direct arc the more certain one:
  // 200 equal measurements divide its covariance by 200.
  for (int i = 0; i < 199; ++i)
    m.add_arc_measurement(0, 3,
                          PoseGaussian(Pose2D(6, 0, 0), diag(1.0, 1.0, 0.2)));
  tree = shortest_paths(m, 0);
  EXPECT_EQ(tree.path_to(3), (std::vector<AreaId>{0, 3}));
  EXPECT_NEAR(tree.nodes.at(3).cost, (1.0 + 1.0 + 0.04) / 200, 1e-12);
  // From 2, area 0 is still reached through 1: the way through 3 is two
  // short arcs as well, but 2 -> 3's heading variance (0.0004) acts on the
  // 6 m arc after it, 2 -> 1's only on a 2 m one.
  const PathTree from2 = shortest_paths(m, 2);
  EXPECT_EQ(from2.path_to(0), (std::vector<AreaId>{2, 1, 0}));
  EXPECT_LT(from2.nodes.at(0).cost,
            path_cost(compose_path(m, {2, 3, 0}).cov));
}

TEST(ShortestPaths, AngleLengthScaleTradesHeadingAgainstPosition) {
  // Route A (via 1) ends uncertain in heading, route B (via 2) in position.
  HmtMap m = areas(4);
  const Eigen::Matrix3d certain = diag(0.05, 0.05, 0.01);  // xy 0.005, th 1e-4
  const Eigen::Matrix3d heading = diag(0.05, 0.05, 0.5);   // xy 0.005, th 0.25
  const Eigen::Matrix3d position = diag(0.2, 0.2, 0.01);   // xy 0.08, th 1e-4
  m.add_arc_measurement(0, 1, PoseGaussian(Pose2D(1, 1, 0), certain));
  m.add_arc_measurement(1, 3, PoseGaussian(Pose2D(1, -1, 0), heading));
  m.add_arc_measurement(0, 2, PoseGaussian(Pose2D(1, -1, 0), position));
  m.add_arc_measurement(2, 3, PoseGaussian(Pose2D(1, 1, 0), position));
  // l = 1 m: A = 0.0102 + 0.2501 loses to B = 0.1602 + 0.0002.
  EXPECT_NEAR(path_cost(heading), 0.255, 1e-15);
  EXPECT_EQ(shortest_paths(m, 0).path_to(3), (std::vector<AreaId>{0, 2, 3}));
  // l = 0.1 m: heading matters less, A = 0.0102 + 0.0025 wins.
  PathCostOptions o;
  o.angle_length_scale = 0.1;
  EXPECT_NEAR(path_cost(heading, o), 0.005 + 0.0025, 1e-15);
  EXPECT_EQ(shortest_paths(m, 0, o).path_to(3), (std::vector<AreaId>{0, 1, 3}));
  o.angle_length_scale = 0.0;
  EXPECT_THROW(shortest_paths(m, 0, o), std::invalid_argument);
  EXPECT_THROW(shortest_paths(m, 9), std::out_of_range);
}

TEST(ShortestPaths, ALongLoopOfSharpArcsDoesNotBeatTheDirectArc) {
  // Two neighbours 0 and 1 joined by an arc of 0.22 m, and the long way
  // round a 200 m loop of 20 arcs, each millimetre-sharp in position (as
  // fine alignments make them) but two of them 1.2 degrees unsure in
  // heading. Summed arc traces prefer the loop (0.001 against 0.1); its
  // composed prior is metres wide, the direct arc's is not.
  HmtMap m = areas(21);
  m.add_arc_measurement(0, 1, PoseGaussian(Pose2D(1, 0, 0), diag(0.22, 0.22, 0.055)));
  const Eigen::Matrix3d sharp = diag(0.002, 0.002, 0.0005);
  const Eigen::Matrix3d unsure = diag(0.002, 0.002, 0.021);
  // 0 -> 2 -> ... -> 20 -> 1: out 100 m and back, turning once.
  AreaId prev = 0;
  for (AreaId a = 2; a <= 20; ++a) {
    const Pose2D step = a == 11 ? Pose2D(10, 0, M_PI) : Pose2D(10, 0, 0);
    m.add_arc_measurement(prev, a, PoseGaussian(step, a == 4 || a == 6 ? unsure : sharp));
    prev = a;
  }
  m.add_arc_measurement(20, 1, PoseGaussian(Pose2D(10, 0, M_PI), sharp));
  const PoseGaussian loop = compose_path(m, {0, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14,
                                             15, 16, 17, 18, 19, 20, 1});
  EXPECT_GT(std::sqrt(loop.cov(1, 1)), 1.0);  // the lever arms of 100 m
  const PathTree tree = shortest_paths(m, 0);
  EXPECT_EQ(tree.path_to(1), (std::vector<AreaId>{0, 1}));
  EXPECT_LT(std::sqrt(tree.pose_of(1).cov(1, 1)), 0.25);
}

TEST(ShortestPaths, EqualCostsGiveADeterministicTree) {
  // A diamond with equal arcs: 3 is reached through the smaller id, 1.
  HmtMap m = areas(4);
  const Eigen::Matrix3d c = diag(0.1, 0.1, 0.01);
  m.add_arc_measurement(0, 2, PoseGaussian(Pose2D(1, -1, 0), c));
  m.add_arc_measurement(0, 1, PoseGaussian(Pose2D(1, 1, 0), c));
  m.add_arc_measurement(2, 3, PoseGaussian(Pose2D(1, 1, 0), c));
  m.add_arc_measurement(1, 3, PoseGaussian(Pose2D(1, -1, 0), c));
  for (int i = 0; i < 3; ++i)
    EXPECT_EQ(shortest_paths(m, 0).path_to(3), (std::vector<AreaId>{0, 1, 3}));
  EXPECT_EQ(shortest_paths(m, 3).path_to(0), (std::vector<AreaId>{3, 1, 0}));
}

}  // namespace
}  // namespace hmt::topology

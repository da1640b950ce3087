#include "hmt/tsbi/match_field.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "hmt/common/random.h"
#include "hmt/metric_slam/scan_matcher.h"
#include "test_maps.h"

namespace hmt::tsbi {
namespace {

using topology::PoseGaussian;
using test_maps::diag;
using test_maps::map_of;
using test_maps::observe;

constexpr grid::LogOdds kOccupied = 10;

TEST(MatchField, DistanceIsChebyshevToTheNearestObstacle) {
  grid::OccupancyGrid g(0.05);
  const std::vector<grid::CellIndex> obstacles = {{3, 4}, {10, -2}, {-5, 7}};
  for (const auto& c : obstacles) g.mutable_logodds(c) = 40;
  g.mutable_logodds({0, 0}) = 5;     // below the threshold: not an obstacle
  g.mutable_logodds({20, 20}) = -30; // free
  const MatchField f(g, kOccupied);
  for (int y = -30; y <= 30; ++y)
    for (int x = -30; x <= 30; ++x) {
      int truth = MatchField::kFar;
      for (const auto& c : obstacles)
        truth = std::min(truth, std::max(std::abs(x - c.x), std::abs(y - c.y)));
      const bool inside = x >= -5 && x <= 10 && y >= -2 && y <= 7;  // the obstacles' box
      if (inside)
        EXPECT_EQ(f.distance(x, y), truth) << x << "," << y;
      else
        EXPECT_LE(f.distance(x, y), truth) << x << "," << y;  // a lower bound outside
    }
  EXPECT_EQ(f.distance(13, 7), 3);
  EXPECT_EQ(f.distance_at(3 * 0.05 + 0.01, 4 * 0.05 + 0.04), 0);
}

TEST(MatchField, ScatteredObstaclesGiveTheBruteForceDistancesCappedAtFar) {
  // A box of 640 x 90 cells: obstacles at its two ends and a cluster at the
  // left, so that the middle lies farther than kFar from all of them.
  grid::OccupancyGrid g(0.05);
  Random rng(7);
  std::vector<grid::CellIndex> obstacles = {{0, 0}, {639, 89}};
  for (int k = 0; k < 150; ++k)
    obstacles.push_back({static_cast<int>(rng.uniform() * 120), static_cast<int>(rng.uniform() * 90)});
  for (const auto& c : obstacles) g.mutable_logodds(c) = 40;
  const MatchField f(g, kOccupied);
  int capped = 0;
  for (int y = 0; y < 90; ++y)
    for (int x = 0; x < 640; ++x) {
      int truth = MatchField::kFar;
      for (const auto& c : obstacles)
        truth = std::min(truth, std::max(std::abs(x - c.x), std::abs(y - c.y)));
      ASSERT_EQ(f.distance(x, y), truth) << x << "," << y;
      capped += truth == MatchField::kFar;
    }
  EXPECT_GT(capped, 0);
}

TEST(MatchField, AMapWithoutObstaclesIsFarEverywhere) {
  grid::OccupancyGrid g(0.05);
  g.mutable_logodds({1, 1}) = -20;
  const MatchField f(g, kOccupied);
  EXPECT_FALSE(f.has_obstacles());
  EXPECT_EQ(f.distance(1, 1), MatchField::kFar);
  EXPECT_FALSE(may_reach_ratio(f, {{1.0, 0.0}}, PoseGaussian(Pose2D(), diag(1, 1)), 16.27, 0.1,
                               1, 1000));
}

struct Office {
  std::shared_ptr<const grid::OccupancyGrid> map =
      map_of(testing_sim::office_world(), Pose2D(),
             {{2, 2, 0}, {4, 4, 1.5}, {6, 8, 3.0}, {2, 8, -1.5}});
  metric_slam::ScanMatcher matcher{metric_slam::MatcherOptions{}};
  MatchField field{*map, matcher.occupied_threshold()};
  Pose2D truth{3, 3, 0.2};
  Observations obs = observe(testing_sim::office_world(), {{2.5, 2.9, 0.2}, truth});
  double ratio_at(const Pose2D& p) const {
    return static_cast<double>(matcher.score(*map, p, obs.points).matched) /
           static_cast<double>(obs.points.hit.size());
  }
};

// Soundness: whatever the prior, if some pose in its gate matches a ratio
// r, the bound must not rule r out.
TEST(MayReachRatio, NeverRulesOutARatioThatAPoseInTheGateReaches) {
  Office o;
  const int window = o.matcher.options().window;
  Random rng(7);
  for (int trial = 0; trial < 40; ++trial) {
    // A prior whose gate holds the truth, often far from its mean.
    const double sxy = 0.05 + 0.5 * rng.uniform(), sth = 0.01 + 0.2 * rng.uniform();
    const Pose2D off(rng.normal() * sxy, rng.normal() * sxy, rng.normal() * sth);
    const PoseGaussian prior(o.truth + off, diag(sxy, sth));
    // The best ratio among the truth, the match from it and random poses in
    // the gate.
    double best = o.ratio_at(o.truth);
    const Pose2D match = o.matcher.optimize(*o.map, o.truth, o.obs.points, nullptr);
    const Eigen::Vector3d em = topology::difference(match, prior.mean);
    if (em.dot(prior.cov.inverse() * em) <= 16.27) best = std::max(best, o.ratio_at(match));
    for (int k = 0; k < 30; ++k) {
      const Pose2D p(prior.mean.x + rng.normal() * sxy, prior.mean.y + rng.normal() * sxy,
                     prior.mean.theta + rng.normal() * sth);
      const Eigen::Vector3d e = topology::difference(p, prior.mean);
      if (e.dot(prior.cov.inverse() * e) <= 16.27) best = std::max(best, o.ratio_at(p));
    }
    const Eigen::Vector3d e = topology::difference(o.truth, prior.mean);
    if (e.dot(prior.cov.inverse() * e) > 16.27) continue;
    EXPECT_TRUE(may_reach_ratio(o.field, o.obs.points.hit, prior, 16.27, best, window, 1000000))
        << "trial " << trial << " ratio " << best;
  }
  EXPECT_GT(o.ratio_at(o.truth), 0.5);  // the map explains most of the scans
}

TEST(MayReachRatio, RulesOutPlacesTheMapCannotExplain) {
  Office o;
  const int window = o.matcher.options().window;
  // A corridor's scans: nowhere near the truth's prior do 60% of them land
  // on the office's walls.
  const Observations corridor =
      observe(testing_sim::corridor_world(), {{10, 1.5, 0.0}, {10.5, 1.5, 0.0}});
  const PoseGaussian prior(o.truth, diag(0.3, 0.1));
  EXPECT_FALSE(may_reach_ratio(o.field, corridor.points.hit, prior, 16.27, 0.6, window, 1000000));
  // The office's own scans, but the prior 2 m and half a turn away.
  const PoseGaussian wrong(o.truth + Pose2D(2.0, 1.0, 1.5), diag(0.1, 0.03));
  EXPECT_FALSE(may_reach_ratio(o.field, o.obs.points.hit, wrong, 16.27, 0.6, window, 1000000));
  // ... and the right prior keeps them.
  EXPECT_TRUE(may_reach_ratio(o.field, o.obs.points.hit, PoseGaussian(o.truth, diag(0.3, 0.1)),
                              16.27, 0.6, window, 1000000));
}

// The bound compares counts against the least count whose ratio passes:
// exactly k of n points reachable passes a ratio of k / n and fails one
// just above it, as the ratio gate's own division decides.
TEST(MayReachRatio, PassesARatioOfExactlyTheReachablePointsAndNoMore) {
  grid::OccupancyGrid g(0.05);
  for (const grid::CellIndex c : {grid::CellIndex{20, 0}, {0, 20}, {-20, 0}})
    g.mutable_logodds(c) = 100;
  const MatchField f(g, kOccupied);
  // Three points on the obstacles, two 5 m from any of them.
  const std::vector<Point2D> pts{{1.025, 0.025}, {0.025, 1.025}, {-0.975, 0.025},
                                 {5.0, 5.0}, {-5.0, 5.0}};
  const PoseGaussian tight(Pose2D(), diag(0.001, 0.001));
  EXPECT_TRUE(may_reach_ratio(f, pts, tight, 16.27, 3.0 / 5.0, 1, 1000));
  EXPECT_TRUE(may_reach_ratio(f, pts, tight, 16.27, 0.0, 1, 1000));
  EXPECT_FALSE(may_reach_ratio(f, pts, tight, 16.27, std::nextafter(3.0 / 5.0, 1.0), 1, 1000));
  EXPECT_FALSE(may_reach_ratio(f, pts, tight, 16.27, 1.0, 1, 1000));
}

TEST(MayReachRatio, GivesUpAsMaybeWhenTheBudgetRunsOut) {
  Office o;
  const Observations corridor =
      observe(testing_sim::corridor_world(), {{10, 1.5, 0.0}, {10.5, 1.5, 0.0}});
  // A gate so broad that the first boxes cannot decide.
  const PoseGaussian broad(o.truth, diag(3.0, 1.0));
  EXPECT_TRUE(may_reach_ratio(o.field, corridor.points.hit, broad, 16.27, 0.6, 1, 2));
}

}  // namespace
}  // namespace hmt::tsbi

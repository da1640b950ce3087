#include "hmt/tsbi/bnb_matcher.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>

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

// A random world: an outer box and a few random walls inside it.
std::vector<testing_sim::Segment> random_world(Random& rng) {
  std::vector<testing_sim::Segment> w = {{0, 0, 12, 0}, {12, 0, 12, 8}, {12, 8, 0, 8}, {0, 8, 0, 0}};
  const int walls = 3 + static_cast<int>(rng.uniform() * 6);
  for (int k = 0; k < walls; ++k) {
    const double x = rng.uniform(1, 11), y = rng.uniform(1, 7), a = rng.uniform(-M_PI, M_PI);
    const double len = rng.uniform(0.5, 3.0);
    w.push_back({x, y, x + len * std::cos(a), y + len * std::sin(a)});
  }
  return w;
}

TEST(CostStack, EachLevelIsTheLeastCostOverItsBlock) {
  Random rng(3);
  grid::OccupancyGrid g(0.05);
  for (int k = 0; k < 40; ++k)
    g.mutable_logodds({static_cast<int>(rng.uniform(-30, 30)), static_cast<int>(rng.uniform(-20, 20))}) = 40;
  const MatchField f(g, kOccupied);
  for (int step : {1, 3}) {
    const int window = 2;
    const CostStack stack(f, window, step, 5);
    ASSERT_EQ(stack.levels(), 5);
    EXPECT_EQ(stack.max_cost(), 25);
    for (int trial = 0; trial < 3000; ++trial) {
      const int level = static_cast<int>(rng.uniform() * 5);
      const int x = static_cast<int>(rng.uniform(-80, 80)), y = static_cast<int>(rng.uniform(-70, 70));
      int truth = stack.max_cost();
      for (int b = 0; b < (1 << level); ++b)
        for (int a = 0; a < (1 << level); ++a)
          truth = std::min(truth, CostStack::point_cost(f.distance(x + a * step, y + b * step), window));
      ASSERT_EQ(stack.cost(level, x, y), truth) << "level " << level << " at " << x << "," << y;
    }
  }
}

TEST(CostStack, AMapWithoutObstaclesCostsTheMaximumEverywhere) {
  grid::OccupancyGrid g(0.05);
  g.mutable_logodds({0, 0}) = -20;
  const CostStack stack(MatchField(g, kOccupied), 3, 1, 4);
  EXPECT_EQ(stack.max_cost(), 49);
  EXPECT_EQ(stack.cost(0, 0, 0), 49);
  EXPECT_EQ(stack.cost(3, -5, 2), 49);
  EXPECT_EQ(stack.bytes(), 0u);
}

TEST(GateLattice, BlockTestNeverDropsAPoseInTheGate) {
  Random rng(11);
  for (int trial = 0; trial < 30; ++trial) {
    Eigen::Matrix3d A = Eigen::Matrix3d::Random();
    const Eigen::Matrix3d cov = A * A.transpose() * 0.05 + diag(0.05, 0.02);
    const SearchLattice l = gate_lattice(PoseGaussian(Pose2D(1, 2, 0.3), cov), 9.0, 0.05, 0.02, 0.05);
    for (int t = -l.nt; t <= l.nt; t += 3)
      for (int j = -l.ny; j <= l.ny; j += 4)
        for (int i = -l.nx; i <= l.nx; i += 4) {
          bool any = false;
          for (int b = j; b < j + 4 && !any; ++b)
            for (int a = i; a < i + 4 && !any; ++a) any = l.in_gate(a, b, t);
          if (any) {
            ASSERT_TRUE(l.block_meets_gate(i, i + 3, j, j + 3, t));
          }
        }
  }
}

// On random maps, observations and windows, the branch and bound returns
// exactly the exhaustive search's modes: the same poses with the same costs
// in the same order, all inside the gate.
TEST(BnbModes, EqualTheExhaustiveSearchOnRandomWindows) {
  Random rng(5);
  metric_slam::ScanMatcher matcher{metric_slam::MatcherOptions{}};
  const int window = matcher.options().coarse_window;
  int compared = 0, multi = 0;
  for (int trial = 0; trial < 24; ++trial) {
    const auto world = random_world(rng);
    const auto map = map_of(world, Pose2D(), {{3, 3, 0.3}, {8, 5, 2.0}, {6, 2, -1.0}});
    const MatchField field(*map, matcher.occupied_threshold());
    const Pose2D truth(rng.uniform(2, 10), rng.uniform(2, 6), rng.uniform(-M_PI, M_PI));
    const Observations obs = observe(world, {truth});
    const auto pts = metric_slam::spread_subset(obs.points, 40 + trial * 5).hit;
    const double sxy = rng.uniform(0.05, 0.25), sth = rng.uniform(0.01, 0.08);
    const Pose2D mean = truth + Pose2D(rng.normal() * sxy, rng.normal() * sxy, rng.normal() * sth);
    const int step = 1 + trial % 2;
    const SearchLattice l = gate_lattice(PoseGaussian(mean, diag(sxy, sth)), 16.27,
                                         step * 0.05, rng.uniform(0.005, 0.02), 0.05);
    const CostStack stack(field, window, step, 2 + trial % 6);
    ModeQuery q;
    q.count = 1 + trial % 8;
    q.separation_xy = rng.uniform(0.05, 0.4);
    q.separation_theta = rng.uniform(0.01, 0.1);
    // A third of the trials keep only modes near the best's cost.
    if (trial % 3 == 0) q.margin = static_cast<int64_t>(pts.size()) * 2;
    auto want = exhaustive_modes(field, window, l, pts, q);
    // Half the trials with a cost limit that leaves some modes out (the
    // modes under a limit are those of no limit that cost no more).
    if (trial % 2 && want.size() > 1) {
      q.max_cost = want[want.size() / 2].cost;
      while (want.back().cost > q.max_cost) want.pop_back();
    }
    SearchStats stats;
    const auto got = bnb_modes(stack, l, pts, q, &stats);
    ASSERT_EQ(got.size(), want.size()) << "trial " << trial;
    for (size_t k = 0; k < got.size(); ++k) {
      EXPECT_EQ(got[k].cost, want[k].cost) << "trial " << trial << " mode " << k;
      EXPECT_EQ(got[k].i, want[k].i) << "trial " << trial << " mode " << k;
      EXPECT_EQ(got[k].j, want[k].j) << "trial " << trial << " mode " << k;
      EXPECT_EQ(got[k].t, want[k].t) << "trial " << trial << " mode " << k;
      EXPECT_TRUE(l.in_gate(got[k].i, got[k].j, got[k].t));
      if (k > 0) {
        EXPECT_LE(got[k - 1].cost, got[k].cost);
      }
    }
    // Under a budget of blocks the search stops early, with a prefix of
    // the modes.
    ModeQuery budget = q;
    budget.max_blocks = std::max<int64_t>(1, stats.blocks / 2);
    SearchStats cut;
    const auto part = bnb_modes(stack, l, pts, budget, &cut);
    EXPECT_FALSE(stats.stopped);
    if (cut.stopped) {
      EXPECT_LE(part.size(), got.size());
    } else {
      EXPECT_EQ(part.size(), got.size());
    }
    for (size_t k = 0; k < part.size() && k < got.size(); ++k)
      EXPECT_EQ(part[k].cost, got[k].cost) << "trial " << trial << " mode " << k;
    ++compared;
    multi += got.size() > 1;
    // The bound pruned: fewer blocks than the lattice has poses.
    const int64_t lattice = static_cast<int64_t>(2 * l.nx + 1) * (2 * l.ny + 1) * (2 * l.nt + 1);
    if (lattice > 20000) {
      EXPECT_LT(stats.blocks, lattice) << "trial " << trial;
    }
  }
  EXPECT_EQ(compared, 24);
  EXPECT_GT(multi, 8);  // the top-K comparison was exercised
}

TEST(BnbModes, ACostLimitNobodyReachesLeavesNoMode) {
  metric_slam::ScanMatcher matcher{metric_slam::MatcherOptions{}};
  const auto world = testing_sim::office_world();
  const auto map = map_of(world, Pose2D(), {{2, 2, 0}, {4, 4, 1.5}});
  const MatchField field(*map, matcher.occupied_threshold());
  const Observations obs = observe(world, {{3, 3, 0.2}});
  const auto pts = metric_slam::spread_subset(obs.points, 100).hit;
  const SearchLattice l = gate_lattice(PoseGaussian(Pose2D(3, 3, 0.2), diag(0.2, 0.05)),
                                       16.27, 0.05, 0.01, 0.05);
  const CostStack stack(field, 2, 1, 6);
  ModeQuery q;
  const auto best = bnb_modes(stack, l, pts, q);
  ASSERT_FALSE(best.empty());
  q.max_cost = best[0].cost - 1;
  EXPECT_TRUE(bnb_modes(stack, l, pts, q).empty());
}

// A loop closed after a long tour: the prior's mean is 0.3 m and 0.02 rad
// from the truth, but its spread (40 m, 0.7 rad) is what many arcs composed
// give; the area is a long block of offices, so most roots of the gate's
// box meet its map.
struct LongLoop {
  metric_slam::ScanMatcher matcher{metric_slam::MatcherOptions{}};
  std::vector<testing_sim::Segment> world = long_offices();
  std::shared_ptr<const grid::OccupancyGrid> map =
      map_of(world, Pose2D(), {{4, 3, 0}, {14, 3, 0}, {24, 3, 0}, {34, 3, 0}, {44, 3, 0}});
  MatchField field{*map, matcher.occupied_threshold()};
  Pose2D truth{23.3, 2.7, 0.2};
  std::vector<Point2D> pts = metric_slam::spread_subset(observe(world, {truth}).points, 100).hit;
  PoseGaussian prior{truth + Pose2D(0.3, -0.2, 0.02), diag(40.0, 0.7)};
  CostStack stack{field, matcher.options().coarse_window, 1, 6};

  // Offices 5 m wide either side of a 6 m hall, 50 m long.
  static std::vector<testing_sim::Segment> long_offices() {
    std::vector<testing_sim::Segment> w = {{0, 0, 50, 0}, {50, 0, 50, 6}, {50, 6, 0, 6}, {0, 6, 0, 0}};
    for (double x = 5; x < 50; x += 5) {
      w.push_back({x, 0, x, 1.5 + 0.1 * x / 5});
      w.push_back({x + 1, 6, x + 1, 4.2 - 0.1 * x / 5});
    }
    return w;
  }
};

TEST(BudgetLattice, IsTheGateLatticeWhereItsRootsFitTheBudget) {
  const LongLoop s;
  const SearchLattice full = gate_lattice(s.prior, 16.27, 0.05, 0.01, 0.05);
  const int64_t roots = roots_on_map(s.stack, full, s.pts);
  ASSERT_GT(roots, 1000);
  // The box's roots at every heading bound those on the map.
  const int b = 1 << root_level(full, s.stack.levels());
  EXPECT_LE(roots, int64_t{2 * full.nt + 1} * ((2 * full.nx) / b + 1) * ((2 * full.ny) / b + 1));
  const SearchLattice same = budget_lattice(s.stack, full, s.pts, roots);
  EXPECT_EQ(same.gate, full.gate);
  EXPECT_EQ(same.nx, full.nx);
  EXPECT_EQ(same.ny, full.ny);
  EXPECT_EQ(same.nt, full.nt);
  // Narrowed as far as the budget needs, about the same mean, and no further.
  const SearchLattice narrow = budget_lattice(s.stack, full, s.pts, roots / 10);
  EXPECT_LE(roots_on_map(s.stack, narrow, s.pts), roots / 10);
  const SearchLattice wider = gate_lattice(s.prior, narrow.gate / 0.8, 0.05, 0.01, 0.05);
  EXPECT_GT(roots_on_map(s.stack, wider, s.pts), roots / 10);
  EXPECT_LT(narrow.gate, full.gate);
  EXPECT_EQ(narrow.center.x, full.center.x);
  EXPECT_EQ(narrow.information, full.information);
  for (int t : {-narrow.nt, 0, narrow.nt})
    EXPECT_EQ(narrow.pose(3, -2, t).theta, full.pose(3, -2, t).theta);
}

TEST(BnbModes, APriorWiderThanTheBudgetIsSearchedOverItsMostProbablePart) {
  // Over the whole gate the budget runs out among the roots of the first
  // headings bounded -- the gate's edge -- and the truth is never reached;
  // over the part of the gate the budget covers it is found.
  const LongLoop s;
  ModeQuery q;
  q.count = 1;
  q.max_blocks = 200000;
  auto found = [&](const std::vector<SearchMode>& modes) {
    return !modes.empty() && (modes[0].pose - s.truth).norm() < 0.1 &&
           std::fabs(wrap_angle(modes[0].pose.theta - s.truth.theta)) < 0.02;
  };
  const SearchLattice full = gate_lattice(s.prior, 16.27, 0.05, 0.01, 0.05);
  ASSERT_GT(roots_on_map(s.stack, full, s.pts), q.max_blocks);
  SearchStats full_stats;
  EXPECT_FALSE(found(bnb_modes(s.stack, full, s.pts, q, &full_stats)));
  EXPECT_TRUE(full_stats.stopped);
  const SearchLattice part = budget_lattice(s.stack, full, s.pts, q.max_blocks / 4);
  SearchStats part_stats;
  EXPECT_TRUE(found(bnb_modes(s.stack, part, s.pts, q, &part_stats)));
  EXPECT_LT(part_stats.blocks, q.max_blocks);
}

}  // namespace
}  // namespace hmt::tsbi

#include "hmt/metric_slam/scan_matcher.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "hmt/common/error.h"
#include "hmt/grid/scan_insertion.h"
#include "sim_world.h"

namespace hmt::metric_slam {
namespace {

TEST(ScanMatcher, RecoversAKnownOffset) {
  const auto world = testing_sim::office_world();
  grid::OccupancyGrid map(0.05);
  const Pose2D truth(4.0, 3.0, 0.3);
  grid::InsertionOptions ins;
  for (int k = 0; k < 3; ++k)
    grid::insert_scan(map, truth, testing_sim::cast_scan(world, truth, 361, M_PI, 30, nullptr, 0), ins);
  MatcherOptions opt;
  ScanMatcher m(opt);
  Random rng(3);
  const LaserScan scan = testing_sim::cast_scan(world, truth, 181, M_PI, 30, &rng, 0.01);
  const ScanPoints pts = prepare_scan(scan, opt.max_range, 0, 0.05);
  const Pose2D start(truth.x + 0.08, truth.y - 0.06, truth.theta + 0.04);
  MatchScore at_start, at_end;
  at_start = m.score(map, start, pts);
  const Pose2D got = m.optimize(map, start, pts, &at_end);
  EXPECT_GT(at_end.log_likelihood, at_start.log_likelihood);
  EXPECT_NEAR(got.x, truth.x, 0.02);
  EXPECT_NEAR(got.y, truth.y, 0.02);
  EXPECT_NEAR(got.theta, truth.theta, 0.01);
  EXPECT_GT(at_end.matched, static_cast<int>(pts.hit.size() * 0.9));
}

TEST(ScanMatcher, EmptyMapExplainsNothing) {
  grid::OccupancyGrid map(0.05);
  MatcherOptions opt;
  ScanMatcher m(opt);
  const auto world = testing_sim::office_world();
  const LaserScan scan = testing_sim::cast_scan(world, Pose2D(4, 3, 0), 181, M_PI, 30, nullptr, 0);
  const ScanPoints pts = prepare_scan(scan, opt.max_range, 0, 0.05);
  EXPECT_EQ(m.score(map, Pose2D(4, 3, 0), pts).matched, 0);
}

// A map whose windows cross tile boundaries, reach an unknown tile column
// and occupied cells of a tile without hit statistics, and 400 beams that
// end around it.
void random_map_and_scan(grid::OccupancyGrid& map, ScanPoints& pts, Random& rng) {
  for (int y = -40; y < 40; ++y)
    for (int x = -40; x < 32; ++x) {  // x >= 32: an unknown tile column
      grid::Cell c;
      const bool occupied = rng.uniform() < 0.3;
      c.logodds = static_cast<grid::LogOdds>(occupied ? 5 + rng.uniform() * 35 : -rng.uniform() * 40);
      // Tile (0, 0) gets occupied cells but no hit statistics at all.
      if (occupied && !(x >= 0 && y >= 0)) {
        c.hits = 1 + static_cast<uint8_t>(rng.uniform() * 20);
        c.hx = static_cast<int8_t>(rng.uniform() * 254 - 127);
        c.hy = static_cast<int8_t>(rng.uniform() * 254 - 127);
      }
      map.set_cell({x, y}, c);
    }
  for (int i = 0; i < 400; ++i) {
    const double r = 0.3 + rng.uniform() * 1.8, a = rng.uniform() * 2 * M_PI;
    pts.hit.push_back({r * std::cos(a), r * std::sin(a)});
    pts.free.push_back({(r - 0.05) * std::cos(a), (r - 0.05) * std::sin(a)});
  }
}

// score() against the likelihood field summed cell by cell through the
// grid's public accessors, for every window radius the options allow.
TEST(ScanMatcher, ScoreIsTheFieldSummedCellByCell) {
  grid::OccupancyGrid map(0.05);
  ScanPoints pts;
  Random rng(11);
  random_map_and_scan(map, pts, rng);
  for (int w = 0; w <= kMaxWindow; ++w) {
    MatcherOptions opt;
    opt.window = w;
    const ScanMatcher m(opt);
    const grid::LogOdds thr = m.occupied_threshold();
    const double max_d2 = (w + 0.5) * (w + 0.5) * 0.05 * 0.05;
    for (int k = 0; k < 20; ++k) {
      const Pose2D pose(rng.uniform() * 0.6 - 0.3, rng.uniform() * 0.6 - 0.3,
                        rng.uniform() * 2 * M_PI - M_PI);
      const double c = std::cos(pose.theta), s = std::sin(pose.theta);
      double sum = 0.0;
      int matched = 0;
      for (size_t i = 0; i < pts.hit.size(); ++i) {
        const Point2D& p = pts.hit[i];
        const Point2D& q = pts.free[i];
        const double hx = pose.x + c * p.x - s * p.y, hy = pose.y + s * p.x + c * p.y;
        const double fx = pose.x + c * q.x - s * q.y, fy = pose.y + s * q.x + c * q.y;
        const grid::CellIndex hc = map.cell_of(hx, hy), fc = map.cell_of(fx, fy);
        double best = std::numeric_limits<double>::infinity();
        for (int dy = -w; dy <= w; ++dy)
          for (int dx = -w; dx <= w; ++dx) {
            const grid::CellIndex cq{hc.x + dx, hc.y + dy};
            const grid::Cell cell = map.cell(cq);
            if (cell.logodds < thr || map.cell({fc.x + dx, fc.y + dy}).logodds >= thr) continue;
            const Point2D mean = map.hit_mean(cq, cell);
            best = std::min(best, (hx - mean.x) * (hx - mean.x) + (hy - mean.y) * (hy - mean.y));
          }
        if (best == std::numeric_limits<double>::infinity()) continue;
        sum += std::min(best, max_d2);
        ++matched;
      }
      const double expected =
          -(sum + (static_cast<double>(pts.hit.size()) - matched) * max_d2) /
          (2 * opt.sigma * opt.sigma);
      const MatchScore got = m.score(map, pose, pts);
      ASSERT_EQ(got.matched, matched) << "window " << w << ", pose " << k;
      ASSERT_DOUBLE_EQ(got.log_likelihood, expected) << "window " << w << ", pose " << k;
    }
  }
}

// The lattice's shared scoring of one heading's translations is score() of
// each pose, to the bit, whatever the window.
TEST(ScanMatcher, SameHeadingScoresAreScores) {
  grid::OccupancyGrid map(0.05);
  ScanPoints pts;
  Random rng(12);
  random_map_and_scan(map, pts, rng);
  for (int w = 0; w <= kMaxWindow; ++w) {
    MatcherOptions opt;
    opt.window = w;
    const ScanMatcher m(opt);
    for (int k = 0; k < 5; ++k) {
      const Pose2D centre(rng.uniform() * 0.6 - 0.3, rng.uniform() * 0.6 - 0.3,
                          rng.uniform() * 2 * M_PI - M_PI);
      Pose2D poses[9];
      for (int t = 0; t < 9; ++t)  // steps below a cell: many share cells
        poses[t] = Pose2D(centre.x + (t % 3 - 1) * 0.02, centre.y + (t / 3 - 1) * 0.02, centre.theta);
      MatchScore got[9];
      m.score_same_heading(map, poses, 9, pts, got);
      for (int t = 0; t < 9; ++t) {
        const MatchScore want = m.score(map, poses[t], pts);
        ASSERT_EQ(got[t].matched, want.matched) << "window " << w << ", pose " << t;
        ASSERT_EQ(got[t].log_likelihood, want.log_likelihood) << "window " << w << ", pose " << t;
      }
    }
    Pose2D mixed[2] = {Pose2D(0, 0, 0), Pose2D(0, 0, 0.1)};
    MatchScore out[2];
    EXPECT_THROW(m.score_same_heading(map, mixed, 2, pts, out), Error);
  }
}

}  // namespace
}  // namespace hmt::metric_slam

#include "hmt/metric_slam/scan_matcher.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace hmt::metric_slam

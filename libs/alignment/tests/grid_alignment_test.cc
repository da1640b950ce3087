#include "hmt/alignment/grid_alignment.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <stdexcept>

#include "synthetic_rooms.h"

namespace hmt::alignment {
namespace {

using testing::crop;
using testing::room_tour_a;
using testing::room_tour_b;
using testing::room_world;
using testing::scanned_grid;

// The pose of the moving grid's frame in the fixed grid's frame (= world).
const Pose2D kTruth(0.3, -0.2, 0.1);

Eigen::Matrix3d diag(double sxy, double st) {
  return Eigen::Vector3d(sxy * sxy, sxy * sxy, st * st).asDiagonal();
}

// The two views of the room, built once: fixed in the world frame, moving
// in the frame kTruth, from different robot positions and noise.
struct Room {
  grid::OccupancyGrid fixed = scanned_grid(room_world(), room_tour_a(), Pose2D(), 1);
  grid::OccupancyGrid moving = scanned_grid(room_world(), room_tour_b(), kTruth, 2);
};
const Room& room() {
  static const Room r;
  return r;
}

void expect_near_truth(const AlignmentResult& r, const Pose2D& truth) {
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_TRUE(r.reason.empty());
  const double dxy = std::hypot(r.pose.mean.x - truth.x, r.pose.mean.y - truth.y);
  const double dth = std::abs(wrap_angle(r.pose.mean.theta - truth.theta));
  EXPECT_LT(dxy, 0.02) << r.pose.mean.x << " " << r.pose.mean.y;
  EXPECT_LT(dth, 0.5 * M_PI / 180.0) << r.pose.mean.theta;
}

void expect_small_positive_definite(const Eigen::Matrix3d& cov) {
  EXPECT_TRUE(topology::is_positive_definite(cov)) << cov;
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvalues()(0), 0.0);
  EXPECT_LT(std::sqrt(cov(0, 0)), 0.02) << cov;
  EXPECT_LT(std::sqrt(cov(1, 1)), 0.02) << cov;
  EXPECT_LT(std::sqrt(cov(2, 2)), 0.005) << cov;
}

TEST(GridAlignment, PointsAreTheOccupiedCellsAtTheirHitMeans) {
  grid::OccupancyGrid g(0.1);
  grid::Cell a;
  a.logodds = 40;
  a.hits = 2;
  a.hx = 127;  // +0.5 cell
  a.hy = -127;
  g.set_cell({3, -2}, a);
  g.mutable_logodds({4, 4}) = 40;  // occupied but never hit: no point
  grid::Cell free;
  free.logodds = -40;
  free.hits = 3;
  g.set_cell({5, 5}, free);
  const auto pts = occupied_points(g, AlignmentOptions{});
  ASSERT_EQ(pts.size(), 1u);
  EXPECT_NEAR(pts[0].x, 0.35 + 0.1 * 127 / grid::kHitScale, 1e-12);
  EXPECT_NEAR(pts[0].y, -0.15 - 0.1 * 127 / grid::kHitScale, 1e-12);
}

TEST(GridAlignment, AlignsTheRoomFromGuessesOffByFifteenCentimetresAndThreeDegrees) {
  const Room& r = room();
  // Four guesses, each 0.15 m and 0.05 rad away from the truth.
  const double dirs[4] = {0.0, 2.0, 3.5, 5.0};
  for (int k = 0; k < 4; ++k) {
    SCOPED_TRACE(k);
    const double sign = (k % 2) ? -1.0 : 1.0;
    const Pose2D guess(kTruth.x + 0.15 * std::cos(dirs[k]),
                       kTruth.y + 0.15 * std::sin(dirs[k]),
                       kTruth.theta + sign * 0.05);
    const topology::PoseGaussian init(guess, diag(0.2, 0.1));
    const AlignmentResult res = align_grids(r.moving, r.fixed, init, AlignmentOptions{});
    expect_near_truth(res, kTruth);
    expect_small_positive_definite(res.pose.cov);
    EXPECT_GT(res.inlier_ratio, 0.8);
    EXPECT_LT(res.rmse, 0.03);
    EXPECT_GT(res.iterations, 0);
    EXPECT_GT(res.moving_points, 1000);
    EXPECT_GT(res.fixed_points, 1000);
  }
}

TEST(GridAlignment, TheInverseProblemGivesTheInversePose) {
  const Room& r = room();
  const Pose2D truth = kTruth.inverse();
  const Pose2D guess = truth + Pose2D(-0.1, 0.11, -0.05);
  const AlignmentResult res = align_grids(
      r.fixed, r.moving, topology::PoseGaussian(guess, diag(0.2, 0.1)), AlignmentOptions{});
  expect_near_truth(res, truth);
}

TEST(GridAlignment, CovarianceReflectsTheResidualsAndTheInflation) {
  const Room& r = room();
  const topology::PoseGaussian init(kTruth + Pose2D(0.1, 0.1, 0.03), diag(0.2, 0.1));
  AlignmentOptions opt;
  const AlignmentResult a = align_grids(r.moving, r.fixed, init, opt);
  opt.covariance_inflation *= 4.0;
  const AlignmentResult b = align_grids(r.moving, r.fixed, init, opt);
  ASSERT_TRUE(a.ok && b.ok) << a.reason << b.reason;
  const Eigen::Matrix3d floor = diag(opt.sigma_floor_xy, opt.sigma_floor_theta);
  // Above the floor, the covariance scales with the inflation factor.
  EXPECT_TRUE(((b.pose.cov - floor) - 4.0 * (a.pose.cov - floor)).norm() <
              1e-9 * a.pose.cov.norm());
  // The residuals add to the floor (here the floor dominates: the truth is
  // recovered to a millimetre).
  EXPECT_GT(a.pose.cov(0, 0), floor(0, 0));
  EXPECT_GT(a.pose.cov(2, 2), floor(2, 2));
  EXPECT_TRUE(topology::is_positive_definite(a.pose.cov - floor));

  // Two grids from the very same noiseless scans: the residuals vanish, the
  // floor keeps the covariance positive definite.
  const grid::OccupancyGrid same =
      scanned_grid(room_world(), room_tour_a(), Pose2D(), 1, 0.0);
  const AlignmentResult c = align_grids(
      same, same, topology::PoseGaussian(Pose2D(0.05, -0.05, 0.02), diag(0.2, 0.1)), opt);
  ASSERT_TRUE(c.ok) << c.reason;
  EXPECT_LT(c.pose.mean.norm(), 1e-4);
  EXPECT_LT(std::abs(c.pose.mean.theta), 1e-5);
  EXPECT_LT(c.rmse, 1e-6);
  EXPECT_TRUE(topology::is_positive_definite(c.pose.cov));
  EXPECT_NEAR(c.pose.cov(0, 0), floor(0, 0), 1e-9);
}

TEST(GridAlignment, AGuessOutsideTheGateIsRejected) {
  const Room& r = room();
  // The same guess as above but claimed to be good to 1 cm / 0.3 degrees:
  // the alignment finds the truth, 15 cm away, which the guess rules out.
  const Pose2D guess(kTruth.x + 0.15, kTruth.y, kTruth.theta + 0.05);
  const AlignmentResult res = align_grids(
      r.moving, r.fixed, topology::PoseGaussian(guess, diag(0.01, 0.005)),
      AlignmentOptions{});
  EXPECT_FALSE(res.ok);
  EXPECT_NE(res.reason.find("implausibly far"), std::string::npos) << res.reason;
  // The pose it reached is still reported, for diagnostics.
  EXPECT_LT(std::hypot(res.pose.mean.x - kTruth.x, res.pose.mean.y - kTruth.y), 0.02);

  // A wider gate accepts it.
  AlignmentOptions wide;
  wide.gate_chi2 = 1e4;
  EXPECT_TRUE(align_grids(r.moving, r.fixed,
                          topology::PoseGaussian(guess, diag(0.01, 0.005)), wide)
                  .ok);
}

TEST(GridAlignment, EmptyOrFeaturelessGridsAreRejected) {
  const Room& r = room();
  const topology::PoseGaussian init(kTruth, diag(0.2, 0.1));
  const grid::OccupancyGrid empty(0.05);
  for (const AlignmentResult& res :
       {align_grids(empty, r.fixed, init, AlignmentOptions{}),
        align_grids(r.moving, empty, init, AlignmentOptions{})}) {
    EXPECT_FALSE(res.ok);
    EXPECT_NE(res.reason.find("too few points"), std::string::npos) << res.reason;
  }

  // Free space only: the walls of the hall are beyond the insertion range
  // (20 m), so its scan marks free cells and no hit.
  sim::World hall;
  hall.box(-40, -40, 40, 40);
  sim::Sensor far;
  far.max_range = 80.0;
  grid::OccupancyGrid open(0.05);
  grid::insert_scan(open, Pose2D(), sim::raycast(hall, Pose2D(), far),
                    grid::InsertionOptions{});
  grid::CellIndex lo, hi;
  ASSERT_TRUE(open.bounds(&lo, &hi));  // the grid is not empty, only free
  EXPECT_LT(open.probability(open.cell_of(5.0, 5.0)), 0.5);
  const AlignmentResult res = align_grids(open, r.fixed, init, AlignmentOptions{});
  EXPECT_FALSE(res.ok);
  EXPECT_EQ(res.moving_points, 0);
  EXPECT_NE(res.reason.find("too few points"), std::string::npos) << res.reason;
}

// A corridor 3 m wide and 60 m long, optionally with a niche every 5 m on
// alternating sides, scanned from its middle.
sim::World corridor(bool niches) {
  sim::World w;
  w.wall(0, 0, 60, 0);
  w.wall(0, 3, 60, 3);
  for (int k = 0; niches && 5.0 * k + 3.5 < 60; ++k) {
    const double x = 2.0 + 5.0 * k + 0.7 * (k % 3);
    const double y = (k % 2) ? 3.0 : 0.0, d = (k % 2) ? -0.4 : 0.4;
    w.wall(x, y, x, y + d);
    w.wall(x, y + d, x + 0.6, y + d);
    w.wall(x + 0.6, y + d, x + 0.6, y);
  }
  return w;
}

TEST(GridAlignment, WallsThatDoNotFixThePoseAreIllConditioned) {
  const Pose2D frame(1.0, 0.1, 0.02);
  const topology::PoseGaussian init(frame + Pose2D(0.1, 0.05, 0.01), diag(0.3, 0.1));
  // One straight wall: plenty of points, nothing fixes the position along it.
  sim::World wall;
  wall.wall(-30, 2, 30, 2);
  const AlignmentResult one = align_grids(
      scanned_grid(wall, {{-4.3, 0.4, 2.0}, {1.7, -0.3, -0.2}, {7.1, 0.2, 0.3}}, frame, 5),
      scanned_grid(wall, {{-6, 0, 0}, {0, 0, 0.5}, {6, 0, 1.0}}, Pose2D(), 4), init,
      AlignmentOptions{});
  EXPECT_FALSE(one.ok);
  EXPECT_NE(one.reason.find("ill-conditioned"), std::string::npos) << one.reason;
  EXPECT_GT(one.moving_points, 200);
  EXPECT_LT(one.information_ratio, 0.01);

  // A featureless corridor, of which the scans see neither end.
  const std::vector<Pose2D> tour_f = {{22, 1.5, 0}, {28, 1.4, 0.5}, {34, 1.6, 1.0}};
  const std::vector<Pose2D> tour_m = {{23.3, 1.5, 2.0}, {28.7, 1.3, -0.2}, {33.1, 1.6, 0.3}};
  const AlignmentResult plain =
      align_grids(scanned_grid(corridor(false), tour_m, frame, 5),
                  scanned_grid(corridor(false), tour_f, Pose2D(), 4), init,
                  AlignmentOptions{});
  EXPECT_FALSE(plain.ok);
  EXPECT_NE(plain.reason.find("ill-conditioned"), std::string::npos) << plain.reason;

  // The same corridor with niches is well conditioned and aligns.
  const AlignmentResult niches =
      align_grids(scanned_grid(corridor(true), tour_m, frame, 5),
                  scanned_grid(corridor(true), tour_f, Pose2D(), 4), init,
                  AlignmentOptions{});
  expect_near_truth(niches, frame);
  EXPECT_GT(niches.information_ratio, 0.1);
}

TEST(GridAlignment, HalfTheRoomStillAligns) {
  const Room& r = room();
  // The moving grid keeps only the west half of the room.
  const grid::OccupancyGrid half =
      crop(r.moving, kTruth, [](const Point2D& p) { return p.x < 10.0; });
  const topology::PoseGaussian init(kTruth + Pose2D(0.1, -0.11, 0.05), diag(0.2, 0.1));
  const AlignmentResult res = align_grids(half, r.fixed, init, AlignmentOptions{});
  expect_near_truth(res, kTruth);
  expect_small_positive_definite(res.pose.cov);
  EXPECT_LT(res.moving_points, 0.7 * align_grids(r.moving, r.fixed, init,
                                                 AlignmentOptions{}).moving_points);
}

TEST(GridAlignment, OverlappingHalvesAlignAndOnlyTheOverlapCounts) {
  const Room& r = room();
  // Moving sees x < 13, fixed sees x > 6 (world): the shared strip holds
  // about half of moving's points. Moving's points where fixed saw nothing
  // are no evidence against the alignment: the inlier ratio is over the
  // overlap, and stays as high as for the whole room.
  const grid::OccupancyGrid west =
      crop(r.moving, kTruth, [](const Point2D& p) { return p.x < 13.0; });
  const grid::OccupancyGrid east =
      crop(r.fixed, Pose2D(), [](const Point2D& p) { return p.x > 6.0; });
  const topology::PoseGaussian init(kTruth + Pose2D(-0.1, 0.11, -0.05), diag(0.2, 0.1));
  const AlignmentResult res = align_grids(west, east, init, AlignmentOptions{});
  expect_near_truth(res, kTruth);
  EXPECT_GT(res.inlier_ratio, 0.8);
  EXPECT_GT(res.overlap_points, 0.2 * res.moving_points);
  EXPECT_LT(res.overlap_points, 0.8 * res.moving_points);
}

TEST(GridAlignment, WallsWhereTheFixedGridSawFreeSpaceLowerTheInlierRatio) {
  const Room& r = room();
  // The moving grid's room has furniture the fixed grid's has not: its walls
  // fall where the fixed grid saw free space, and contradict it.
  sim::World furnished = testing::room_world();
  furnished.wall(8.5, 11.5, 12.5, 11.5);
  furnished.wall(14.5, 3.0, 14.5, 11.0);
  furnished.wall(1.5, 8.0, 5.5, 8.0);
  furnished.wall(9.0, 2.0, 9.0, 6.5);
  const grid::OccupancyGrid moving =
      testing::scanned_grid(furnished, testing::room_tour_b(), kTruth, 2);
  const topology::PoseGaussian init(kTruth + Pose2D(0.05, -0.05, 0.02), diag(0.2, 0.1));
  const AlignmentResult plain = align_grids(r.moving, r.fixed, init, AlignmentOptions{});
  AlignmentOptions lax;
  lax.min_inlier_ratio = 0.0;
  const AlignmentResult res = align_grids(moving, r.fixed, init, lax);
  ASSERT_TRUE(plain.ok) << plain.reason;
  ASSERT_TRUE(res.ok) << res.reason;
  EXPECT_LT(res.inlier_ratio, plain.inlier_ratio - 0.1);
  // ... and the threshold applies to it.
  AlignmentOptions strict;
  strict.min_inlier_ratio = 0.5 * (res.inlier_ratio + plain.inlier_ratio);
  const AlignmentResult rej = align_grids(moving, r.fixed, init, strict);
  EXPECT_FALSE(rej.ok);
  EXPECT_NE(rej.reason.find("inlier ratio"), std::string::npos) << rej.reason;
}

TEST(GridAlignment, IsDeterministic) {
  const Room& r = room();
  const topology::PoseGaussian init(kTruth + Pose2D(0.12, 0.09, -0.05), diag(0.2, 0.1));
  const AlignmentResult a = align_grids(r.moving, r.fixed, init, AlignmentOptions{});
  // A copy of the grids (shared tiles) and a fresh run.
  const grid::OccupancyGrid moving = r.moving, fixed = r.fixed;
  const AlignmentResult b = align_grids(moving, fixed, init, AlignmentOptions{});
  ASSERT_TRUE(a.ok);
  EXPECT_EQ(a.ok, b.ok);
  EXPECT_EQ(a.pose.mean.x, b.pose.mean.x);
  EXPECT_EQ(a.pose.mean.y, b.pose.mean.y);
  EXPECT_EQ(a.pose.mean.theta, b.pose.mean.theta);
  EXPECT_EQ(a.pose.cov, b.pose.cov);
  EXPECT_EQ(a.inlier_ratio, b.inlier_ratio);
  EXPECT_EQ(a.rmse, b.rmse);
  EXPECT_EQ(a.iterations, b.iterations);
}

TEST(GridAlignment, RejectsAnInitialCovarianceThatIsNotPositiveDefinite) {
  const Room& r = room();
  EXPECT_THROW(align_grids(r.moving, r.fixed, topology::PoseGaussian(kTruth),
                           AlignmentOptions{}),
               std::invalid_argument);
}

}  // namespace
}  // namespace hmt::alignment

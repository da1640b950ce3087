#include "hmt/alignment/icp.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "synthetic_rooms.h"

namespace hmt::alignment {
namespace {

// An asymmetric "room" outline, points 2 to 8 cm apart. Irregularly: on
// evenly spaced points, point-to-point ICP can settle with every point
// paired to its neighbour's match, a fraction of the spacing off.
std::vector<Point2D> outline(const Point2D& offset = {0.0, 0.0}) {
  std::vector<Point2D> pts;
  double phase = 0.0;
  const auto segment = [&](double x0, double y0, double x1, double y1) {
    const double len = std::hypot(x1 - x0, y1 - y0);
    for (double s = 0.0; s < len;) {
      pts.push_back({offset.x + x0 + (x1 - x0) * s / len, offset.y + y0 + (y1 - y0) * s / len});
      phase = std::fmod(phase + 0.618034, 1.0);  // golden-ratio sequence
      s += 0.02 + 0.06 * phase;
    }
  };
  segment(0, 0, 8, 0);
  segment(8, 0, 8, 5);
  segment(8, 5, 3, 5);
  segment(3, 5, 3, 3);
  segment(3, 3, 0, 3);
  segment(0, 3, 0, 0);
  segment(5, 1, 6, 1.5);  // a slanted obstacle
  return pts;
}

// The points of `fixed` as seen from the frame whose pose in fixed's frame
// is `truth`.
std::vector<Point2D> seen_from(const std::vector<Point2D>& fixed, const Pose2D& truth) {
  const Pose2D inv = truth.inverse();
  std::vector<Point2D> out;
  for (const Point2D& p : fixed) out.push_back(inv.transform(p));
  return out;
}

void expect_pose_near(const Pose2D& a, const Pose2D& b, double xy, double th) {
  EXPECT_NEAR(a.x, b.x, xy);
  EXPECT_NEAR(a.y, b.y, xy);
  EXPECT_NEAR(wrap_angle(a.theta - b.theta), 0.0, th);
}

TEST(Icp, RecoversARigidTransformOfTheSamePoints) {
  const std::vector<Point2D> fixed = outline();
  const Pose2D truth(0.4, -0.3, 0.08);
  const std::vector<Point2D> moving = seen_from(fixed, truth);
  const IcpResult r =
      icp_register(moving, fixed, truth + Pose2D(0.15, -0.1, 0.04), AlignmentOptions{});
  expect_pose_near(r.pose, truth, 1e-9, 1e-10);
  EXPECT_EQ(r.pairs, static_cast<int>(moving.size()));
  EXPECT_GT(r.iterations, 4);  // at least the five thresholds 1 m ... 6 cm
}

TEST(Icp, KeepsItsPrecisionFarFromTheOrigin) {
  // Coordinates of a kilometre: the fit works on centred sums.
  const std::vector<Point2D> fixed = outline({1000.0, -2000.0});
  const Pose2D truth(1000.3, -1999.8, -0.05);
  const std::vector<Point2D> moving = seen_from(fixed, truth);
  const IcpResult r =
      icp_register(moving, fixed, truth + Pose2D(-0.1, 0.1, 0.03), AlignmentOptions{});
  expect_pose_near(r.pose, truth, 1e-7, 1e-10);
}

TEST(Icp, PairsWithinTheThresholdPlusTheAngularTermOnly) {
  // Four fixed points 2.5 m apart, 10 m from the origin; the moving ones
  // displaced 0.9 m.
  const std::vector<Point2D> fixed = {{10.0, 0.0}, {10.0, 2.5}, {12.5, 0.0}, {12.5, 2.5}};
  std::vector<Point2D> moving;
  for (const Point2D& p : fixed) moving.push_back({p.x + 0.9, p.y});
  AlignmentOptions opt;
  opt.icp_threshold_start = 0.5;
  opt.icp_threshold_angular = 0.0;
  const IcpResult none = icp_register(moving, fixed, Pose2D(), opt);
  EXPECT_EQ(none.pairs, 0);
  EXPECT_EQ(none.iterations, 1);
  expect_pose_near(none.pose, Pose2D(), 0.0, 0.0);

  // 0.5 m + 0.05 rad x (at least) 10.9 m reaches them.
  opt.icp_threshold_angular = 0.05;
  const IcpResult some = icp_register(moving, fixed, Pose2D(), opt);
  EXPECT_EQ(some.pairs, 4);
  expect_pose_near(some.pose, Pose2D(-0.9, 0.0, 0.0), 1e-12, 1e-12);

  // The angular term is measured from the pose's position, not the origin:
  // started at (10, 0), at most 4.2 m from the points, it adds < 0.21 m.
  const Pose2D near(10.0, 0.0, 0.0);
  std::vector<Point2D> local;
  for (const Point2D& p : moving) local.push_back(near.inverse().transform(p));
  EXPECT_EQ(icp_register(local, fixed, near, opt).pairs, 0);
}

TEST(Icp, OutOfIterationsItStillEndsAtTheFineThreshold) {
  const std::vector<Point2D> fixed = outline();
  const Pose2D truth(0.4, -0.3, 0.08);
  const std::vector<Point2D> moving = seen_from(fixed, truth);
  AlignmentOptions opt;
  opt.icp_max_iterations = 1;
  const IcpResult r = icp_register(moving, fixed, truth + Pose2D(0.05, 0.05, 0.01), opt);
  // Thresholds 1, 0.5, 0.25, 0.125, 0.0625 m: at most five rounds, fewer when
  // the pose settles in one of them (then it decays twice).
  EXPECT_GT(r.iterations, 1);
  EXPECT_LE(r.iterations, 5);
  expect_pose_near(r.pose, truth, 0.02, 0.01);
}

TEST(Icp, EmptyPointSetsReturnTheStart) {
  const Pose2D start(1.0, 2.0, 0.3);
  for (const IcpResult& r : {icp_register({}, outline(), start, AlignmentOptions{}),
                             icp_register(outline(), {}, start, AlignmentOptions{})}) {
    expect_pose_near(r.pose, start, 0.0, 0.0);
    EXPECT_EQ(r.iterations, 0);
    EXPECT_EQ(r.pairs, 0);
  }
}

TEST(Icp, IsDeterministicOnNoisyGrids) {
  using testing::room_tour_a;
  using testing::room_tour_b;
  using testing::room_world;
  using testing::scanned_grid;
  const Pose2D truth(0.3, -0.2, 0.1);
  const AlignmentOptions opt;
  const std::vector<Point2D> fixed =
      occupied_points(scanned_grid(room_world(), room_tour_a(), Pose2D(), 1), opt);
  const std::vector<Point2D> moving =
      occupied_points(scanned_grid(room_world(), room_tour_b(), truth, 2), opt);
  const Pose2D start = truth + Pose2D(0.12, 0.09, -0.05);
  const IcpResult a = icp_register(moving, fixed, start, opt);
  const IcpResult b = icp_register(moving, fixed, start, opt);
  EXPECT_EQ(a.pose.x, b.pose.x);
  EXPECT_EQ(a.pose.y, b.pose.y);
  EXPECT_EQ(a.pose.theta, b.pose.theta);
  EXPECT_EQ(a.iterations, b.iterations);
  expect_pose_near(a.pose, truth, 0.01, 0.005);
}

}  // namespace
}  // namespace hmt::alignment

#include "hmt/area/landmark_sso.h"

#include <gtest/gtest.h>

#include <cmath>

#include "hmt/area/sso.h"
#include "hmt/common/random.h"

namespace hmt::area {
namespace {

// World landmarks seen from `robot` within `range`, with noise-free means and
// the covariance a range-bearing sensor of the given noise would report.
LandmarkObservation observe(const std::vector<Point2D>& world,
                            const Pose2D& robot, double range, double sr = 0.05,
                            double sb = 0.01) {
  LandmarkObservation o;
  const Pose2D inv = robot.inverse();
  for (const Point2D& w : world) {
    const Point2D p = inv.transform(w);
    const double r = std::hypot(p.x, p.y);
    if (r > range) continue;
    o.landmarks.push_back(
        landmark_from_range_bearing(Pose2D(), r, std::atan2(p.y, p.x), sr, sb));
  }
  return o;
}

std::vector<Point2D> random_landmarks(Random& rng, int n, double x0,
                                      double x1) {
  std::vector<Point2D> out;
  for (int i = 0; i < n; ++i)
    out.push_back({rng.uniform(x0, x1), rng.uniform(-5, 5)});
  return out;
}

TEST(area_LandmarkSso, IdentityOneDisjointZeroSymmetricInRange) {
  Random rng(3);
  const auto world = random_landmarks(rng, 60, 0, 30);
  SsoOptions o;
  for (int k = 0; k < 10; ++k) {
    const Pose2D pa(rng.uniform(0, 30), rng.uniform(-2, 2), rng.uniform(-3, 3));
    const Pose2D pb(rng.uniform(0, 30), rng.uniform(-2, 2), rng.uniform(-3, 3));
    const auto a = observe(world, pa, 8.0), b = observe(world, pb, 8.0);
    if (a.landmarks.empty()) continue;
    EXPECT_DOUBLE_EQ(landmark_sso(a, PoseGaussian(pa), a, PoseGaussian(pa), o),
                     1.0);
    const double ab = landmark_sso(a, PoseGaussian(pa), b, PoseGaussian(pb), o);
    EXPECT_DOUBLE_EQ(ab,
                     landmark_sso(b, PoseGaussian(pb), a, PoseGaussian(pa), o));
    EXPECT_GE(ab, 0.0);
    EXPECT_LE(ab, 1.0);
  }
  // Landmarks 100 m away from the others.
  const auto other = random_landmarks(rng, 20, 100, 110);
  const auto a = observe(world, Pose2D(10, 0, 0), 50.0);
  const auto c = observe(other, Pose2D(105, 0, 0), 50.0);
  EXPECT_DOUBLE_EQ(landmark_sso(a, PoseGaussian(Pose2D(10, 0, 0)), c,
                                PoseGaussian(Pose2D(105, 0, 0)), o),
                   0.0);
}

TEST(area_LandmarkSso, CountsCommonLandmarksOverTheAverageCount) {
  // 10 landmarks; A sees the first 8, B the last 6 -> 4 in common.
  std::vector<Point2D> world;
  for (int i = 0; i < 10; ++i) world.push_back({2.0 * i, (i % 3) - 1.0});
  const Pose2D pa(3, 0.5, 0.2), pb(12, -0.5, 2.8);
  LandmarkObservation a, b;
  const auto all_a = observe(world, pa, 100), all_b = observe(world, pb, 100);
  a.landmarks.assign(all_a.landmarks.begin(), all_a.landmarks.begin() + 8);
  b.landmarks.assign(all_b.landmarks.begin() + 4, all_b.landmarks.end());
  SsoOptions o;
  EXPECT_EQ(count_landmark_matches(a, PoseGaussian(pa), b, PoseGaussian(pb), o),
            4u);
  EXPECT_DOUBLE_EQ(landmark_sso(a, PoseGaussian(pa), b, PoseGaussian(pb), o),
                   4.0 / ((8.0 + 6.0) / 2.0));
}

TEST(area_LandmarkSso, MahalanobisGateOnEq15) {
  // One landmark; B's estimate of it is displaced. Covariances: each side
  // isotropic 0.1^2, pose exact -> the difference has variance 0.02 per axis.
  Landmark la;
  la.mean = Eigen::Vector2d(4, 1);
  la.cov = Eigen::Matrix2d::Identity() * 0.01;
  const Pose2D pa(0, 0, 0), pb(1, 0, M_PI / 2);
  auto b_with_offset = [&](double off) {
    // The landmark's world position (4, 1 + off) as seen from pb.
    const Point2D p = pb.inverse().transform({4.0, 1.0 + off});
    Landmark lb;
    lb.mean = Eigen::Vector2d(p.x, p.y);
    lb.cov = Eigen::Matrix2d::Identity() * 0.01;
    return LandmarkObservation{{lb}};
  };
  const LandmarkObservation a{{la}};
  SsoOptions o;
  o.gate = 9.0;  // "below 3" standard deviations
  const double sd = std::sqrt(0.02);
  EXPECT_DOUBLE_EQ(landmark_sso(a, PoseGaussian(pa), b_with_offset(2.5 * sd),
                                PoseGaussian(pb), o),
                   1.0);
  EXPECT_DOUBLE_EQ(landmark_sso(a, PoseGaussian(pa), b_with_offset(3.5 * sd),
                                PoseGaussian(pb), o),
                   0.0);
  // Declaring heading uncertainty of pose B widens the gate across the
  // lever arm: the landmark is 3 m from B along x, so a heading error moves
  // it along y, the direction of the offset.
  PoseGaussian gb(pb);
  gb.cov(2, 2) = 0.05 * 0.05;
  EXPECT_DOUBLE_EQ(
      landmark_sso(a, PoseGaussian(pa), b_with_offset(3.5 * sd), gb, o), 1.0);
}

TEST(area_LandmarkSso, DescriptorsMustAlsoMatchWhenRequested) {
  Landmark l1, l2;
  l1.mean = Eigen::Vector2d(2, 0);
  l2.mean = Eigen::Vector2d(2, 0.01);
  l1.cov = l2.cov = Eigen::Matrix2d::Identity() * 0.01;
  l1.descriptor = {1.0f, 0.0f, 0.0f};
  l2.descriptor = {0.0f, 1.0f, 0.0f};  // distance sqrt(2)
  const LandmarkObservation a{{l1}}, b{{l2}};
  const PoseGaussian p;
  SsoOptions o;
  EXPECT_DOUBLE_EQ(landmark_sso(a, p, b, p, o), 1.0);  // descriptors ignored
  o.descriptor_threshold = 1.0;
  EXPECT_DOUBLE_EQ(landmark_sso(a, p, b, p, o), 0.0);
  o.descriptor_threshold = 1.5;
  EXPECT_DOUBLE_EQ(landmark_sso(a, p, b, p, o), 1.0);
}

TEST(area_LandmarkSso, MatchesAreOneToOne) {
  // Two landmarks of A both within the gate of the single landmark of B.
  Landmark x, y, z;
  x.mean = Eigen::Vector2d(3, 0);
  y.mean = Eigen::Vector2d(3, 0.05);
  z.mean = Eigen::Vector2d(3, 0.02);
  x.cov = y.cov = z.cov = Eigen::Matrix2d::Identity() * 0.01;
  const LandmarkObservation a{{x, y}}, b{{z}};
  SsoOptions o;
  EXPECT_EQ(count_landmark_matches(a, PoseGaussian(), b, PoseGaussian(), o),
            1u);
  EXPECT_DOUBLE_EQ(landmark_sso(a, PoseGaussian(), b, PoseGaussian(), o),
                   2.0 / 3.0);
}

TEST(area_ObservationSso, MixesScansAndLandmarksByAveraging) {
  Random rng(5);
  const auto world = random_landmarks(rng, 40, 0, 20);
  const Pose2D pa(5, 0, 0), pb(9, 1, 0.5);
  Observation a, b;
  a.landmark_sets = {observe(world, pa, 10)};
  b.landmark_sets = {observe(world, pb, 10)};
  LaserScan scan;
  scan.angle_min = 0.0f;
  scan.angle_increment = 0.01f;
  scan.max_range = 10.0f;
  scan.ranges.assign(50, 3.0f);
  scan.valid.assign(50, 1);
  a.scans = {scan};
  b.scans = {scan};
  SsoOptions o;
  const double lm = landmark_sso(a.landmark_sets[0], PoseGaussian(pa),
                                 b.landmark_sets[0], PoseGaussian(pb), o);
  const double sc = scan_sso(scan, pa, scan, pb, o);
  EXPECT_NEAR(observation_sso(a, PoseGaussian(pa), b, PoseGaussian(pb), o),
              0.5 * (lm + sc), 1e-12);
  EXPECT_GT(lm, 0.0);
}

}  // namespace
}  // namespace hmt::area

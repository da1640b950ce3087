#include "hmt/area/scan_sso.h"

#include <gtest/gtest.h>

#include <cmath>

#include "hmt/area/pose_gaussian.h"
#include "hmt/area/sso.h"
#include "hmt/common/random.h"
#include "sim_world.h"

namespace hmt::area {
namespace {

// A random scan of a cluttered scene: smooth ranges with random gaps.
LaserScan random_scan(Random& rng, int beams = 180) {
  LaserScan s;
  s.angle_min = static_cast<float>(-M_PI / 2);
  s.angle_increment = static_cast<float>(M_PI / (beams - 1));
  s.max_range = 30.0f;
  double r = rng.uniform(2.0, 8.0);
  for (int i = 0; i < beams; ++i) {
    r = std::clamp(r + rng.normal(0.0, 0.15), 0.5, 25.0);
    s.ranges.push_back(static_cast<float>(r));
    s.valid.push_back(rng.uniform() < 0.9);
  }
  s.sensor_pose = Pose2D(0.2, 0.0, 0.0);
  return s;
}

// Reference: both scans' points in the world frame, O(N M) search.
double brute_force_sso(const LaserScan& a, const Pose2D& pa, const LaserScan& b,
                       const Pose2D& pb, double delta) {
  auto world = [](const LaserScan& s, const Pose2D& p) {
    std::vector<Point2D> out;
    for (size_t i = 0; i < s.size(); ++i) {
      if (!is_valid_return(s, i)) continue;
      const double r = s.ranges[i], t = s.bearing(i);
      out.push_back(
          (p + s.sensor_pose).transform({r * std::cos(t), r * std::sin(t)}));
    }
    return out;
  };
  const auto A = world(a, pa), B = world(b, pb);
  auto ratio = [delta](const std::vector<Point2D>& P,
                       const std::vector<Point2D>& Q) {
    if (P.empty()) return 0.0;
    size_t m = 0;
    for (const auto& p : P)
      for (const auto& q : Q)
        if (std::hypot(p.x - q.x, p.y - q.y) <= delta) {
          ++m;
          break;
        }
    return static_cast<double>(m) / P.size();
  };
  return 0.5 * (ratio(A, B) + ratio(B, A));
}

// The SSO's loop composes its points through one PointComposer: the same
// bits as Pose2D::transform() and the per-point covariance with their own
// sines.
TEST(area_ScanSso, PointComposerGivesTheSameBitsAsThePerPointFunctions) {
  Random rng(3);
  for (int k = 0; k < 200; ++k) {
    PoseGaussian q(Pose2D(rng.uniform(-50, 50), rng.uniform(-50, 50), rng.uniform(-M_PI, M_PI)));
    q.cov << 0.01, 0.002, 0.001, 0.002, 0.02, -0.003, 0.001, -0.003, 0.004;
    const Point2D p{rng.uniform(-30, 30), rng.uniform(-30, 30)};
    Eigen::Matrix2d cp;
    cp << rng.uniform(0.001, 0.1), 0.003, 0.003, rng.uniform(0.001, 0.1);
    const PointComposer through_q(q);
    const Point2D a = through_q.transform(p), b = q.mean.transform(p);
    EXPECT_EQ(a.x, b.x);
    EXPECT_EQ(a.y, b.y);
    const Eigen::Matrix2d ca = through_q.cov(p, cp);
    // The per-point arithmetic as it was, with its own cosine and sine.
    const double c = std::cos(q.mean.theta), s = std::sin(q.mean.theta);
    Eigen::Matrix<double, 2, 3> J;
    J << 1, 0, -s * p.x - c * p.y, 0, 1, c * p.x - s * p.y;
    const Eigen::Matrix2d R = rotation(q.mean.theta);
    const Eigen::Matrix2d cb = J * q.cov * J.transpose() + R * cp * R.transpose();
    EXPECT_TRUE((ca.array() == cb.array()).all()) << ca << "\n" << cb;
  }
}

TEST(area_ScanSso, ScanWithItselfIsOne) {
  Random rng(1);
  SsoOptions o;
  for (int k = 0; k < 20; ++k) {
    const LaserScan s = random_scan(rng);
    const Pose2D p(rng.uniform(-50, 50), rng.uniform(-50, 50),
                   rng.uniform(-3, 3));
    EXPECT_DOUBLE_EQ(scan_sso(s, p, s, p, o), 1.0);
    SsoOptions prob = o;
    prob.use_probabilistic = true;
    EXPECT_DOUBLE_EQ(scan_sso(s, p, s, p, prob), 1.0);
  }
}

TEST(area_ScanSso, MatchesABruteForceReferenceAndIsSymmetric) {
  // Catches a wrong relative pose in either direction: the reference works
  // in the world frame only.
  Random rng(2);
  SsoOptions o;
  o.use_probabilistic = false;  // the reference implements the fixed delta
  o.delta = 0.25;
  for (int k = 0; k < 30; ++k) {
    const LaserScan a = random_scan(rng), b = random_scan(rng);
    const Pose2D pa(rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-3, 3));
    const Pose2D pb = pa + Pose2D(rng.uniform(-1, 1), rng.uniform(-1, 1),
                                  rng.uniform(-0.5, 0.5));
    const double s_ab = scan_sso(a, pa, b, pb, o);
    const double s_ba = scan_sso(b, pb, a, pa, o);
    EXPECT_DOUBLE_EQ(s_ab, s_ba);
    EXPECT_NEAR(s_ab, brute_force_sso(a, pa, b, pb, o.delta), 1e-12);
    EXPECT_GE(s_ab, 0.0);
    EXPECT_LE(s_ab, 1.0);
  }
}

// Reference for the probabilistic test: every pair of points, no search
// radius, the same Mahalanobis gate.
double brute_force_ratio_probabilistic(const PreparedScan& a, const PoseGaussian& pa,
                                       const PreparedScan& b, const PoseGaussian& pb,
                                       const SsoOptions& o) {
  const PoseGaussian q = relative_pose(pa, pb);
  size_t m = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    const Point2D p = q.mean.transform(a.points()[i]);
    Eigen::Matrix2d Cp = compose_point_cov(q, a.points()[i], a.point_covs()[i]);
    Cp.diagonal().array() += kVarianceFloor;
    for (size_t j = 0; j < b.size(); ++j) {
      const Eigen::Vector2d d(p.x - b.points()[j].x, p.y - b.points()[j].y);
      if (mahalanobis2(d, Cp + b.point_covs()[j]) <= o.gate) {
        ++m;
        break;
      }
    }
  }
  return a.empty() ? 0.0 : static_cast<double>(m) / static_cast<double>(a.size());
}

TEST(area_ScanSso, ProbabilisticMatchesABruteForceReference) {
  // The search radius is bounded by each query point's range (long beams
  // have wide sampling covariances, short ones narrow): the pruning must
  // never drop a pair the gate accepts. Far ranges, bearing noise and pose
  // uncertainty make the covariances differ widely.
  Random rng(5);
  SsoOptions o;
  o.use_probabilistic = true;
  o.bearing_std = 0.002;
  for (int k = 0; k < 20; ++k) {
    LaserScan a = random_scan(rng), b = random_scan(rng);
    for (float& r : b.ranges) r *= 3.0f;
    const PreparedScan A(a, o), B(b, o);
    PoseGaussian pa(Pose2D(rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-3, 3)));
    PoseGaussian pb(pa.mean + Pose2D(rng.uniform(-1, 1), rng.uniform(-1, 1),
                                     rng.uniform(-0.5, 0.5)));
    if (k % 2) pb.cov.diagonal() << 0.01, 0.02, 1e-3;
    EXPECT_DOUBLE_EQ(scan_match_ratio(A, pa, B, pb, o),
                     brute_force_ratio_probabilistic(A, pa, B, pb, o));
    EXPECT_DOUBLE_EQ(scan_match_ratio(B, pb, A, pa, o),
                     brute_force_ratio_probabilistic(B, pb, A, pa, o));
  }
}

TEST(area_ScanSso, RealScansOfTheSameRoomOverlapAndOfDisjointRoomsDoNot) {
  const sim::World w = sim::three_rooms();
  sim::Sensor sensor;
  const Pose2D p1(2.0, 1.5, 0.3), p2(3.5, 2.0, -1.0), far(20.0 + 2.0, 1.5, 0.3);
  const LaserScan s1 = sim::raycast(w, p1, sensor),
                  s2 = sim::raycast(w, p2, sensor);
  SsoOptions o;
  const double same = scan_sso(s1, p1, s2, p2, o);
  EXPECT_GT(same, 0.3);
  EXPECT_LE(same, 1.0);
  EXPECT_DOUBLE_EQ(scan_sso(s2, p2, s1, p1, o), same);
  // The same scan placed in a disjoint region of the plane.
  EXPECT_DOUBLE_EQ(scan_sso(s1, p1, s1, far + Pose2D(0, 0, 0), o), 0.0);
  EXPECT_DOUBLE_EQ(scan_sso(s1, p1, s2, Pose2D(100, 100, 0), o), 0.0);
}

// Valid beams only in three 10-degree sectors at 0, 90 and 180 degrees, with
// the same range pattern in each sector.
LaserScan three_sector_scan() {
  LaserScan s;
  s.angle_min = 0.0f;
  s.angle_increment = static_cast<float>(M_PI / 180.0);
  s.max_range = 20.0f;
  for (int i = 0; i < 360; ++i) {
    const int k = i % 90;
    const bool on = k < 10 && i < 270;
    s.ranges.push_back(on ? static_cast<float>(5.0 + 0.05 * k) : 0.0f);
    s.valid.push_back(on);
  }
  return s;
}

TEST(area_ScanSso, KnownShiftGivesTheExpectedOverlap) {
  // The scan against itself taken from the robot turned by 90 degrees about
  // its position: the turned scan's sectors fall on 90, 180 and 270 degrees,
  // so 2 of the 3 sectors coincide in both directions -> SSO = 2/3.
  const LaserScan s = three_sector_scan();
  SsoOptions o;
  o.delta = 0.05;
  const Pose2D pa(1.0, -2.0, 0.4);
  const Pose2D pb = pa + Pose2D(0, 0, M_PI / 2);
  EXPECT_NEAR(scan_sso(s, pa, s, pb, o), 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(scan_match_ratio(PreparedScan(s, o), PoseGaussian(pa),
                               PreparedScan(s, o), PoseGaussian(pb), o),
              2.0 / 3.0, 1e-12);
  // Turned by 180 degrees: sectors at 180, 270, 0 -> two coincide again.
  EXPECT_NEAR(scan_sso(s, pa, s, pa + Pose2D(0, 0, M_PI), o), 2.0 / 3.0, 1e-12);
  // Shifted by less than delta: every point keeps its twin. Shifted by 1 m
  // (a sector spans under 1 m, sectors are metres apart): none does.
  EXPECT_DOUBLE_EQ(scan_sso(s, pa, s, pa + Pose2D(0.03, 0.02, 0), o), 1.0);
  EXPECT_DOUBLE_EQ(scan_sso(s, pa, s, pa + Pose2D(0.0, 1.0, 0), o), 0.0);
}

TEST(area_ScanSso, InvalidAndOutOfRangeReadingsAreIgnored) {
  LaserScan s = three_sector_scan();
  PreparedScan p(s, SsoOptions{});
  EXPECT_EQ(p.size(), 30u);
  s.ranges[0] = 25.0f;  // beyond max_range
  s.ranges[1] = std::nanf("");
  EXPECT_EQ(PreparedScan(s, SsoOptions{}).size(), 28u);
  LaserScan empty = s;
  std::fill(empty.valid.begin(), empty.valid.end(), 0);
  EXPECT_DOUBLE_EQ(scan_sso(empty, Pose2D(), empty, Pose2D(), SsoOptions{}),
                   0.0);
  EXPECT_DOUBLE_EQ(scan_sso(s, Pose2D(), empty, Pose2D(), SsoOptions{}), 0.0);
}

TEST(area_ScanSso, ProbabilisticTestAbsorbsPoseUncertainty) {
  // Two scans of the same room; the second pose is off by 0.3 m. With the
  // 0.1 m tolerance almost nothing matches; declaring the pose uncertainty
  // (sigma 0.2 m) lets the Mahalanobis test match again.
  const sim::World w = sim::three_rooms();
  sim::Sensor sensor;
  const Pose2D p1(2.0, 2.0, 0.0), p2(3.0, 2.5, 0.5);
  const LaserScan s1 = sim::raycast(w, p1, sensor),
                  s2 = sim::raycast(w, p2, sensor);
  const Pose2D p2_wrong = p2 + Pose2D(0.3, 0.0, 0.0);
  SsoOptions fixed;
  fixed.use_probabilistic = false;
  fixed.delta = 0.1;
  const double exact = scan_sso(s1, p1, s2, p2, fixed);
  const double off = scan_sso(s1, p1, s2, p2_wrong, fixed);
  EXPECT_GT(exact, 0.5);
  EXPECT_LT(off, 0.5 * exact);

  SsoOptions prob = fixed;
  prob.use_probabilistic = true;
  prob.beta = 0.005;
  const PreparedScan a(s1, prob), b(s2, prob);
  PoseGaussian g1(p1), g2(p2_wrong);
  const double certain = scan_sso(a, g1, b, g2, prob);
  g2.cov.diagonal() << 0.04, 0.04, 1e-4;
  const double uncertain = scan_sso(a, g1, b, g2, prob);
  EXPECT_GT(uncertain, certain + 0.2);
  EXPECT_GT(uncertain, 0.8 * exact);
  EXPECT_DOUBLE_EQ(scan_sso(b, g2, a, g1, prob), uncertain);
  EXPECT_LE(uncertain, 1.0);
}

TEST(area_ScanSso, ProbabilisticSamplingTermGrowsWithRange) {
  // Same scene, poses exact: with beta large enough the sampling term alone
  // lets distant sparse points match.
  const sim::World w = sim::three_rooms();
  sim::Sensor sensor;
  sensor.beams = 90;  // 4-degree steps: sparse far points
  const Pose2D p1(1.0, 2.5, 0.0), p2(4.5, 1.5, 2.0);
  const LaserScan s1 = sim::raycast(w, p1, sensor),
                  s2 = sim::raycast(w, p2, sensor);
  SsoOptions prob;
  prob.use_probabilistic = true;
  prob.range_std = 0.0;
  prob.beta = 1e-4;
  const double tight = scan_sso(s1, p1, s2, p2, prob);
  prob.beta = 0.0;  // the scan's own 4-degree step
  const double loose = scan_sso(s1, p1, s2, p2, prob);
  EXPECT_GT(loose, tight + 0.3);
}

TEST(area_ObservationSso, AveragesSensorsAndSkipsSensorsThatSawNothing) {
  const sim::World w = sim::three_rooms();
  sim::Sensor front, narrow;
  front.fov = M_PI;
  front.beams = 181;
  narrow.fov = 0.5;
  narrow.beams = 30;
  const Pose2D p1(2.0, 2.0, 0.0), p2(3.0, 2.2, 0.3);
  Observation a, b;
  a.scans = {sim::raycast(w, p1, front), sim::raycast(w, p1, narrow)};
  b.scans = {sim::raycast(w, p2, front), sim::raycast(w, p2, narrow)};
  SsoOptions o;
  const double s0 = scan_sso(a.scans[0], p1, b.scans[0], p2, o);
  const double s1 = scan_sso(a.scans[1], p1, b.scans[1], p2, o);
  EXPECT_NEAR(observation_sso(a, PoseGaussian(p1), b, PoseGaussian(p2), o),
              0.5 * (s0 + s1), 1e-12);
  // A third sensor that returned nothing in either observation is left out.
  LaserScan blind = a.scans[1];
  std::fill(blind.valid.begin(), blind.valid.end(), 0);
  a.scans.push_back(blind);
  b.scans.push_back(blind);
  EXPECT_NEAR(observation_sso(a, PoseGaussian(p1), b, PoseGaussian(p2), o),
              0.5 * (s0 + s1), 1e-12);
  EXPECT_DOUBLE_EQ(observation_sso(a, PoseGaussian(p1), a, PoseGaussian(p1), o),
                   1.0);
  b.scans.pop_back();
  EXPECT_THROW(observation_sso(a, PoseGaussian(p1), b, PoseGaussian(p2), o),
               std::invalid_argument);
}

}  // namespace
}  // namespace hmt::area

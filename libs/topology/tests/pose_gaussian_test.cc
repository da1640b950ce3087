#include "hmt/topology/pose_gaussian.h"

#include <gtest/gtest.h>

#include "test_util.h"

#include <Eigen/Dense>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <vector>

namespace hmt::topology {
namespace {

using testing_util::cov_of;
using testing_util::diag;
using testing_util::vec;



// Sample mean and covariance of poses, angles taken relative to `ref` (so a
// spread across +-pi is not torn apart).
struct Moments {
  Pose2D mean;
  Eigen::Matrix3d cov;
};
Moments moments(const std::vector<Pose2D>& s, const Pose2D& ref) {
  Eigen::Vector3d m = Eigen::Vector3d::Zero();
  for (const Pose2D& p : s) m += difference(p, ref);
  m /= static_cast<double>(s.size());
  Eigen::Matrix3d c = Eigen::Matrix3d::Zero();
  for (const Pose2D& p : s) {
    const Eigen::Vector3d d = difference(p, ref) - m;
    c += d * d.transpose();
  }
  c /= static_cast<double>(s.size() - 1);
  return {Pose2D(ref.x + m.x(), ref.y + m.y(), wrap_angle(ref.theta + m.z())),
          c};
}

// Each covariance entry within `rel` of sqrt(C_ii C_jj) (a correlation-scale
// tolerance), each mean component within `sigmas` standard deviations.
void expect_matches(const Moments& mc, const PoseGaussian& g, double rel,
                    double sigmas) {
  const Eigen::Vector3d d = difference(mc.mean, g.mean);
  for (int i = 0; i < 3; ++i)
    EXPECT_LT(std::abs(d(i)), sigmas * std::sqrt(g.cov(i, i))) << "mean " << i;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      EXPECT_NEAR(mc.cov(i, j), g.cov(i, j),
                  rel * std::sqrt(g.cov(i, i) * g.cov(j, j)))
          << "cov(" << i << "," << j << ")";
}

// Central differences of a pose function, angles wrapped.
Eigen::Matrix3d numeric_jacobian(const std::function<Pose2D(const Pose2D&)>& f,
                                 const Pose2D& at) {
  const double h = 1e-6;
  Eigen::Matrix3d J;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d dp = Eigen::Vector3d::Zero();
    dp(k) = h;
    const Pose2D plus(at.x + dp.x(), at.y + dp.y(), at.theta + dp.z());
    const Pose2D minus(at.x - dp.x(), at.y - dp.y(), at.theta - dp.z());
    J.col(k) = difference(f(plus), f(minus)) / (2 * h);
  }
  return J;
}

TEST(PoseGaussian, JacobiansMatchFiniteDifferences) {
  Random rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    const Pose2D a(rng.uniform(-5, 5), rng.uniform(-5, 5),
                   rng.uniform(-3.1, 3.1));
    const Pose2D b(rng.uniform(-5, 5), rng.uniform(-5, 5),
                   rng.uniform(-3.1, 3.1));
    const Eigen::Matrix3d J1 =
        numeric_jacobian([&](const Pose2D& x) { return x + b; }, a);
    const Eigen::Matrix3d J2 =
        numeric_jacobian([&](const Pose2D& x) { return a + x; }, b);
    const Eigen::Matrix3d Ji =
        numeric_jacobian([](const Pose2D& x) { return x.inverse(); }, a);
    EXPECT_LT((J1 - compose_jacobian_first(a, b)).cwiseAbs().maxCoeff(), 1e-6);
    EXPECT_LT((J2 - compose_jacobian_second(a)).cwiseAbs().maxCoeff(), 1e-6);
    EXPECT_LT((Ji - inverse_jacobian(a)).cwiseAbs().maxCoeff(), 1e-6);
  }
}

TEST(PoseGaussian, ComposeWithExactIdentityKeepsTheGaussian) {
  const PoseGaussian g(Pose2D(1, 2, 0.5),
                       cov_of(0.1, 0.2, 0.05, 0.3, -0.2, 0.1));
  const PoseGaussian left = compose(PoseGaussian(Pose2D()), g);
  EXPECT_NEAR(left.mean.x, 1, 1e-15);
  EXPECT_NEAR(left.mean.y, 2, 1e-15);
  EXPECT_NEAR(left.mean.theta, 0.5, 1e-15);
  EXPECT_LT((left.cov - g.cov).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(PoseGaussian, HeadingUncertaintyMovesTheComposedPositionSideways) {
  // A pose at the origin facing +x with only heading uncertainty, then 10 m
  // straight ahead: the end point is uncertain along y (lever arm 10 m).
  const PoseGaussian a(Pose2D(0, 0, 0), cov_of(0, 0, 0.1));
  const PoseGaussian b(Pose2D(10, 0, 0), Eigen::Matrix3d::Zero());
  const PoseGaussian c = compose(a, b);
  EXPECT_NEAR(c.cov(0, 0), 0.0, 1e-15);
  EXPECT_NEAR(c.cov(1, 1), 100 * 0.01, 1e-12);
  EXPECT_NEAR(c.cov(1, 2), 10 * 0.01, 1e-12);
  EXPECT_NEAR(c.cov(2, 2), 0.01, 1e-15);
}

TEST(PoseGaussian, InverseAndRelativeMatchMonteCarlo) {
  Random rng(5);
  const PoseGaussian a(Pose2D(3, -1, 2.8),
                       cov_of(0.2, 0.1, 0.05, 0.4, 0.2, -0.3));
  const PoseGaussian b(Pose2D(-2, 4, -2.9),
                       cov_of(0.15, 0.25, 0.04, -0.2, 0.1, 0.3));
  const int n = 20000;
  std::vector<Pose2D> inv, rel;
  inv.reserve(n);
  rel.reserve(n);
  for (int i = 0; i < n; ++i) {
    const Pose2D sa = sample(a, rng), sb = sample(b, rng);
    inv.push_back(sa.inverse());
    rel.push_back(sb - sa);
  }
  const PoseGaussian gi = inverse(a);
  const PoseGaussian gr = relative(b, a);
  expect_matches(moments(inv, gi.mean), gi, 0.06, 0.1);
  expect_matches(moments(rel, gr.mean), gr, 0.06, 0.1);
  // The mean of `relative` is the SE(2) relative pose.
  const Pose2D exact = b.mean - a.mean;
  EXPECT_NEAR(gr.mean.x, exact.x, 1e-12);
  EXPECT_NEAR(gr.mean.y, exact.y, 1e-12);
}

TEST(PoseGaussian, InverseIsAnInvolution) {
  const PoseGaussian g(Pose2D(3, -1, 2.8),
                       cov_of(0.2, 0.1, 0.05, 0.4, 0.2, -0.3));
  const PoseGaussian back = inverse(inverse(g));
  EXPECT_LT((vec(back.mean) - vec(g.mean)).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((back.cov - g.cov).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(PoseGaussian, SampleHasTheRequestedMoments) {
  Random rng(3);
  const PoseGaussian g(Pose2D(1, 1, 3.1),
                       cov_of(0.3, 0.2, 0.1, 0.5, -0.4, 0.2));
  std::vector<Pose2D> s;
  for (int i = 0; i < 20000; ++i) s.push_back(sample(g, rng));
  for (const Pose2D& p : s) EXPECT_LE(std::abs(p.theta), M_PI);
  expect_matches(moments(s, g.mean), g, 0.04, 0.05);
}

TEST(PoseGaussianFuse, EqualsTheInformationWeightedResult) {
  // Diagonal covariances: each component fuses as a scalar,
  // mu = (mu1/s1^2 + mu2/s2^2) / (1/s1^2 + 1/s2^2), s^2 = 1/(1/s1^2 + 1/s2^2).
  const PoseGaussian a(Pose2D(1.0, 2.0, 0.1), cov_of(0.1, 0.2, 0.05));
  const PoseGaussian b(Pose2D(1.3, 1.6, 0.3), cov_of(0.2, 0.1, 0.1));
  const PoseGaussian f = fuse(a, b);
  auto scalar = [](double m1, double s1, double m2, double s2) {
    const double w1 = 1 / (s1 * s1), w2 = 1 / (s2 * s2);
    return std::make_pair((m1 * w1 + m2 * w2) / (w1 + w2), 1 / (w1 + w2));
  };
  const auto x = scalar(1.0, 0.1, 1.3, 0.2);
  const auto y = scalar(2.0, 0.2, 1.6, 0.1);
  const auto t = scalar(0.1, 0.05, 0.3, 0.1);
  EXPECT_NEAR(f.mean.x, x.first, 1e-12);      // 1.06
  EXPECT_NEAR(f.mean.y, y.first, 1e-12);      // 1.68
  EXPECT_NEAR(f.mean.theta, t.first, 1e-12);  // 0.14
  EXPECT_NEAR(f.mean.x, 1.06, 1e-12);
  EXPECT_NEAR(f.cov(0, 0), x.second, 1e-14);
  EXPECT_NEAR(f.cov(1, 1), y.second, 1e-14);
  EXPECT_NEAR(f.cov(2, 2), t.second, 1e-14);
  EXPECT_NEAR(f.cov(0, 1), 0.0, 1e-15);

  // Correlated covariances: the fused mean zeroes the gradient of the sum of
  // the two Mahalanobis distances, and its information is the sum.
  const PoseGaussian c(Pose2D(0.5, -0.2, -0.4),
                       cov_of(0.3, 0.1, 0.08, 0.6, -0.3, 0.2));
  const PoseGaussian d(Pose2D(0.7, 0.1, -0.1),
                       cov_of(0.1, 0.3, 0.2, -0.5, 0.4, 0.1));
  const PoseGaussian g = fuse(c, d);
  const Eigen::Matrix3d oc = c.cov.inverse(), od = d.cov.inverse();
  const Eigen::Vector3d grad =
      oc * difference(g.mean, c.mean) + od * difference(g.mean, d.mean);
  EXPECT_LT(grad.cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((g.cov.inverse() - (oc + od)).cwiseAbs().maxCoeff(), 1e-8);
  // Fusion is symmetric.
  const PoseGaussian h = fuse(d, c);
  EXPECT_LT((vec(h.mean) - vec(g.mean)).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((h.cov - g.cov).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(PoseGaussianFuse, SameMeasurementTwiceHalvesTheCovariance) {
  const PoseGaussian a(Pose2D(2, -1, 1.2),
                       cov_of(0.2, 0.1, 0.05, 0.3, -0.2, 0.4));
  const PoseGaussian f = fuse(a, a);
  EXPECT_LT((vec(f.mean) - vec(a.mean)).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((f.cov - 0.5 * a.cov).cwiseAbs().maxCoeff(), 1e-14);
  // Four equal measurements: a quarter.
  const PoseGaussian q = fuse(f, f);
  EXPECT_LT((q.cov - 0.25 * a.cov).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(PoseGaussianFuse, AnglesNearPiFuseAcrossTheCut) {
  // pi - 0.01 and -pi + 0.01 are 0.02 apart: the fused heading is pi, not 0.
  const PoseGaussian a(Pose2D(0, 0, M_PI - 0.01), cov_of(0.1, 0.1, 0.1));
  const PoseGaussian b(Pose2D(0, 0, -M_PI + 0.01), cov_of(0.1, 0.1, 0.1));
  const PoseGaussian f = fuse(a, b);
  EXPECT_NEAR(wrap_angle(f.mean.theta - M_PI), 0.0, 1e-12);
  EXPECT_LE(std::abs(f.mean.theta), M_PI);
  EXPECT_NEAR(f.cov(2, 2), 0.005, 1e-14);

  // Unequal weights: 3x the information on b pulls the result 3/4 of the way
  // from a (pi - 0.04) to b (-pi + 0.04, i.e. pi + 0.04): pi + 0.02.
  const PoseGaussian c(Pose2D(0, 0, M_PI - 0.04),
                       cov_of(0.1, 0.1, 0.1 * std::sqrt(3.0)));
  const PoseGaussian d(Pose2D(0, 0, -M_PI + 0.04), cov_of(0.1, 0.1, 0.1));
  const PoseGaussian g = fuse(c, d);
  EXPECT_NEAR(wrap_angle(g.mean.theta - (M_PI + 0.02)), 0.0, 1e-12);
  EXPECT_NEAR(g.mean.theta, -M_PI + 0.02, 1e-12);  // wrapped into (-pi, pi]
}

TEST(PoseGaussianFuse, RejectsCovariancesThatAreNotPositiveDefinite) {
  const PoseGaussian good(Pose2D(), cov_of(0.1, 0.1, 0.1));
  const PoseGaussian zero(Pose2D(), Eigen::Matrix3d::Zero());
  PoseGaussian singular(Pose2D(), cov_of(0.1, 0.1, 0.1, 1.0));  // x == y
  PoseGaussian asym(Pose2D(), cov_of(0.1, 0.1, 0.1));
  asym.cov(0, 1) = 0.001;
  PoseGaussian nan(Pose2D(), cov_of(0.1, 0.1, 0.1));
  nan.cov(2, 2) = std::nan("");
  EXPECT_THROW(fuse(good, zero), std::invalid_argument);
  EXPECT_THROW(fuse(singular, good), std::invalid_argument);
  EXPECT_THROW(fuse(good, asym), std::invalid_argument);
  EXPECT_THROW(fuse(nan, good), std::invalid_argument);
  EXPECT_TRUE(is_positive_definite(good.cov));
  EXPECT_FALSE(is_positive_definite(-good.cov));
  EXPECT_FALSE(is_positive_definite(singular.cov));
}

}  // namespace
}  // namespace hmt::topology

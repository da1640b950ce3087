#include "hmt/topology/pose_gaussian.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <stdexcept>
#include <string>

namespace hmt::topology {
namespace {

Eigen::Matrix3d symmetrised(const Eigen::Matrix3d& m) {
  return 0.5 * (m + m.transpose());
}

}  // namespace

Eigen::Vector3d difference(const Pose2D& b, const Pose2D& a) {
  return {b.x - a.x, b.y - a.y, wrap_angle(b.theta - a.theta)};
}

Eigen::Matrix3d compose_jacobian_first(const Pose2D& a, const Pose2D& b) {
  const double c = std::cos(a.theta), s = std::sin(a.theta);
  Eigen::Matrix3d J;
  J << 1, 0, -s * b.x - c * b.y,  //
      0, 1, c * b.x - s * b.y,    //
      0, 0, 1;
  return J;
}

Eigen::Matrix3d compose_jacobian_second(const Pose2D& a) {
  const double c = std::cos(a.theta), s = std::sin(a.theta);
  Eigen::Matrix3d J;
  J << c, -s, 0,  //
      s, c, 0,    //
      0, 0, 1;
  return J;
}

Eigen::Matrix3d inverse_jacobian(const Pose2D& a) {
  const double c = std::cos(a.theta), s = std::sin(a.theta);
  Eigen::Matrix3d J;
  J << -c, -s, s * a.x - c * a.y,  //
      s, -c, c * a.x + s * a.y,    //
      0, 0, -1;
  return J;
}

PoseGaussian compose(const PoseGaussian& a, const PoseGaussian& b) {
  const Eigen::Matrix3d Ja = compose_jacobian_first(a.mean, b.mean);
  const Eigen::Matrix3d Jb = compose_jacobian_second(a.mean);
  return PoseGaussian(
      a.mean + b.mean,
      symmetrised(Ja * a.cov * Ja.transpose() + Jb * b.cov * Jb.transpose()));
}

PoseGaussian inverse(const PoseGaussian& a) {
  const Eigen::Matrix3d J = inverse_jacobian(a.mean);
  return PoseGaussian(a.mean.inverse(), symmetrised(J * a.cov * J.transpose()));
}

PoseGaussian relative(const PoseGaussian& of, const PoseGaussian& from) {
  return compose(inverse(from), of);
}

bool is_positive_definite(const Eigen::Matrix3d& cov) {
  if (!cov.allFinite()) return false;
  const double scale = cov.cwiseAbs().maxCoeff();
  if (!(scale > 0.0)) return false;
  if ((cov - cov.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale)
    return false;
  const Eigen::LLT<Eigen::Matrix3d> llt(symmetrised(cov));
  if (llt.info() != Eigen::Success) return false;
  // LLT accepts a zero pivot that rounds to a tiny positive value; require
  // every pivot to be a meaningful fraction of the scale.
  const Eigen::Vector3d d = llt.matrixL().toDenseMatrix().diagonal();
  return d.minCoeff() > 1e-12 * std::sqrt(scale);
}

void require_positive_definite(const Eigen::Matrix3d& cov, const char* what) {
  if (!is_positive_definite(cov))
    throw std::invalid_argument(
        std::string(what) +
        ": covariance is not finite, symmetric and positive definite");
}

PoseGaussian fuse(const PoseGaussian& a, const PoseGaussian& b) {
  require_positive_definite(a.cov, "fuse (first Gaussian)");
  require_positive_definite(b.cov, "fuse (second Gaussian)");
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d omega_a = Eigen::LLT<Eigen::Matrix3d>(a.cov).solve(I);
  const Eigen::Matrix3d omega_b = Eigen::LLT<Eigen::Matrix3d>(b.cov).solve(I);
  const Eigen::Matrix3d omega = symmetrised(omega_a + omega_b);
  const Eigen::Matrix3d cov =
      symmetrised(Eigen::LLT<Eigen::Matrix3d>(omega).solve(I));
  // b's mean written next to a's (angle unwrapped), then the information-
  // weighted mean cov (Omega_a mu_a + Omega_b mu_b) = mu_a + cov Omega_b d.
  const Eigen::Vector3d shift = cov * (omega_b * difference(b.mean, a.mean));
  return PoseGaussian(perturbed(a.mean, shift), cov);
}

Pose2D sample(const PoseGaussian& g, Random& rng) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(symmetrised(g.cov));
  const Eigen::Vector3d sd = es.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  const Eigen::Vector3d z(rng.normal(), rng.normal(), rng.normal());
  const Eigen::Vector3d e = es.eigenvectors() * sd.cwiseProduct(z);
  return perturbed(g.mean, e);
}

}  // namespace hmt::topology

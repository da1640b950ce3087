// A planar pose with a Gaussian uncertainty, N(mean, cov), and the operations
// the topological layer needs: composition (the (+) of 002 Eq. 15),
// inversion (an arc read backwards), the relative pose between two poses,
// closed-form fusion (002 Eq. 10) and sampling.
//
// Parameterisation. The covariance is that of the vector (x, y, theta) with
// additive perturbations: a sample is (mean.x + e_x, mean.y + e_y,
// wrap(mean.theta + e_theta)) with e ~ N(0, cov). Every difference of two
// poses that enters a formula is taken in that same space, with the angle
// wrapped into (-pi, pi] (see difference()), so means near +-pi behave.
//
// Propagation is first order: for f(a) the covariance is J cov J^T with J the
// Jacobian at the mean. The SE(2) Jacobians used (c = cos a.theta,
// s = sin a.theta), for c = a (+) b = (a.x + c b.x - s b.y,
// a.y + s b.x + c b.y, a.theta + b.theta):
//
//   d(a (+) b)/da = [ 1 0  -s b.x - c b.y ]     d(a (+) b)/db = [ c -s 0 ]
//                   [ 0 1   c b.x - s b.y ]                     [ s  c 0 ]
//                   [ 0 0         1       ]                     [ 0  0 1 ]
//
// and for (-)a = (-c a.x - s a.y, s a.x - c a.y, -a.theta):
//
//   d((-)a)/da = [ -c -s   s a.x - c a.y ]
//                [  s -c   c a.x + s a.y ]
//                [  0  0        -1       ]
//
// Composed operands are assumed independent (in the HMT map the arcs are,
// 002 Proposition 3 and Eq. 11).
//
// The type itself is hmt::PoseGaussian (hmt/common/pose_gaussian.h), shared
// with the area abstraction; these are the operations on it.
#pragma once

#include <Eigen/Core>

#include "hmt/common/pose2d.h"
#include "hmt/common/pose_gaussian.h"
#include "hmt/common/random.h"

namespace hmt::topology {

using PoseGaussian = hmt::PoseGaussian;

// (b.x - a.x, b.y - a.y, wrap(b.theta - a.theta)): b - a in the space where
// the covariance lives (not the SE(2) relative pose, see relative()).
Eigen::Vector3d difference(const Pose2D& b, const Pose2D& a);

// The Jacobians of the header comment.
Eigen::Matrix3d compose_jacobian_first(const Pose2D& a, const Pose2D& b);
Eigen::Matrix3d compose_jacobian_second(const Pose2D& a);
Eigen::Matrix3d inverse_jacobian(const Pose2D& a);

// a (+) b: b given in the frame a, composed into a's parent frame.
PoseGaussian compose(const PoseGaussian& a, const PoseGaussian& b);
// (-)a: the parent frame seen from a.
PoseGaussian inverse(const PoseGaussian& a);
// of (-) from = ((-)from) (+) of: `of` seen from the frame `from`.
PoseGaussian relative(const PoseGaussian& of, const PoseGaussian& from);

// Closed-form fusion of two independent Gaussian estimates of the same pose
// (the product of Eq. 10 for two factors), in information form:
//   Omega_i = cov_i^-1,  cov = (Omega_a + Omega_b)^-1,
//   mean = cov (Omega_a mu_a + Omega_b mu_b)
// with mu_b written next to mu_a as mu_a + d, d = difference(b.mean,
// a.mean) (b's angle unwrapped to within pi of a's), which simplifies to
//   mean = mu_a + cov Omega_b d,   then the angle wrapped into (-pi, pi].
// Both covariances must be positive definite (throws std::invalid_argument
// otherwise). Fusing a Gaussian with itself keeps the mean and halves the
// covariance; fusion is symmetric in its arguments.
PoseGaussian fuse(const PoseGaussian& a, const PoseGaussian& b);

// Finite, symmetric (to 1e-9 relative) and positive definite (Cholesky).
bool is_positive_definite(const Eigen::Matrix3d& cov);
// Throws std::invalid_argument("<what>: covariance is not ...") unless
// is_positive_definite(cov).
void require_positive_definite(const Eigen::Matrix3d& cov, const char* what);

// One draw: mean + L z (z standard normal, L L^T = cov), angle wrapped.
// Works for semi-definite covariances (L from the eigen-decomposition).
Pose2D sample(const PoseGaussian& g, Random& rng);

}  // namespace hmt::topology

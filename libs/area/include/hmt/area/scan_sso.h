// Sensed-space overlap (SSO) of two range scans taken at known poses.
//
// Directional match ratio (001 Eq. 17): Pi(A, B) = fraction of A's valid
// points that have a point of B "at the same place". A's points are moved into
// B's frame with the relative pose (pose_A - pose_B), i.e. A seen from B; the
// other direction uses (pose_B - pose_A). The SSO is the symmetric average
// (001 Eq. 18):  SSO(A, B) = (Pi(A, B) + Pi(B, A)) / 2, which is in [0, 1],
// symmetric, 1 for a scan with itself and 0 for scans of disjoint space.
//
// "At the same place" is either
//  - the fixed tolerance of 001 Eq. 16: Euclidean distance <= delta, or
//  - the probabilistic test of 000 Eq. 16: squared Mahalanobis distance of the
//    difference <= gate, where each point's covariance is
//      J diag(Sigma_pose, Sigma_sensor) J^T + sigma_f^2 I,  sigma_f = r beta,
//    Sigma_pose being the covariance of the relative pose (for A's points;
//    B's points are in their own frame and carry sensor noise only).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "hmt/area/area_options.h"
#include "hmt/area/point_grid.h"
#include "hmt/area/pose_gaussian.h"
#include "hmt/common/sensor_data.h"

namespace hmt::checkpoint {
struct Access;  // hmt/checkpoint/checkpoint.h
}  // namespace hmt::checkpoint

namespace hmt::area {

// A scan's valid returns as points in the robot frame, with what the SSO
// needs precomputed once per scan: the per-point measurement covariance and a
// PointGrid (cells of 2 delta). Build once per keyframe and reuse for every
// pair the keyframe takes part in.
class PreparedScan {
  // Checkpoints save and restore every member, bit for bit.
  friend struct hmt::checkpoint::Access;

 public:
  PreparedScan() = default;
  PreparedScan(const LaserScan& scan, const SsoOptions& options);

  size_t size() const { return points_.size(); }
  bool empty() const { return points_.empty(); }
  // Valid returns in the robot frame (sensor_pose folded in).
  const std::vector<Point2D>& points() const { return points_; }
  // Range of each point [m].
  const std::vector<double>& ranges() const { return ranges_; }
  // Robot-frame covariance of each point from sensor noise and sampling
  // (R_s Sigma_s R_s^T + sigma_f^2 I), for the probabilistic test.
  const std::vector<Eigen::Matrix2d>& point_covs() const { return covs_; }
  // Largest eigenvalue over point_covs() (bounds the search radius).
  double max_point_var() const { return max_var_; }
  // A tighter bound by range: every point j at range r_j from the sensor has
  // lambda_max(point_covs()[j]) <= var_floor() + var_per_range2() * r_j^2
  // (the sampling term r beta and the bearing noise grow with range), so a
  // point near a query close to the sensor needs only a small search radius.
  double var_floor() const { return var_floor_; }
  double var_per_range2() const { return var_per_range2_; }
  // The sensor's position in the robot frame.
  const Point2D& sensor_origin() const { return origin_; }
  const PointGrid& grid() const { return grid_; }

 private:
  std::vector<Point2D> points_;
  std::vector<double> ranges_;
  std::vector<Eigen::Matrix2d> covs_;
  double max_var_ = 0.0;
  double var_floor_ = 0.0, var_per_range2_ = 0.0;
  Point2D origin_;
  PointGrid grid_;
};

// True for a reading the SSO uses: flagged valid, finite, 0 < r < max_range.
bool is_valid_return(const LaserScan& scan, size_t i);

// Pi(A, B): the fraction of A's points matched in B (0 when A is empty).
double scan_match_ratio(const PreparedScan& a, const PoseGaussian& pose_a,
                        const PreparedScan& b, const PoseGaussian& pose_b,
                        const SsoOptions& options);

// (Pi(A, B) + Pi(B, A)) / 2.
double scan_sso(const PreparedScan& a, const PoseGaussian& pose_a,
                const PreparedScan& b, const PoseGaussian& pose_b,
                const SsoOptions& options);

// Convenience for one pair of raw scans at exactly known poses.
double scan_sso(const LaserScan& a, const Pose2D& pose_a, const LaserScan& b,
                const Pose2D& pose_b, const SsoOptions& options);

// Largest eigenvalue of a symmetric 2x2 matrix.
inline double max_eigenvalue(const Eigen::Matrix2d& m) {
  const double h = 0.5 * (m(0, 0) + m(1, 1));
  const double d = 0.5 * (m(0, 0) - m(1, 1));
  return h + std::sqrt(d * d + m(0, 1) * m(0, 1));
}

// d^T S^-1 d for a symmetric positive definite 2x2 S.
inline double mahalanobis2(const Eigen::Vector2d& d, const Eigen::Matrix2d& S) {
  const double det = S(0, 0) * S(1, 1) - S(0, 1) * S(0, 1);
  return (S(1, 1) * d.x() * d.x() - 2.0 * S(0, 1) * d.x() * d.y() +
          S(0, 0) * d.y() * d.y()) /
         det;
}

// Variance added to every matching covariance so that exactly known inputs
// (all covariances zero) still give a finite Mahalanobis distance: it then
// accepts only coincident positions (within about sqrt(gate) micrometres).
constexpr double kVarianceFloor = 1e-12;

}  // namespace hmt::area

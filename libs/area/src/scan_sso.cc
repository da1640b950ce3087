#include "hmt/area/scan_sso.h"

#include "hmt/area/keyframe.h"

#include <algorithm>
#include <cmath>

namespace hmt::area {

size_t valid_returns(const LaserScan& scan) {
  size_t n = 0;
  for (size_t i = 0; i < scan.size(); ++i) n += is_valid_return(scan, i);
  return n;
}

bool is_valid_return(const LaserScan& scan, size_t i) {
  if (i < scan.valid.size() && !scan.valid[i]) return false;
  const float r = scan.ranges[i];
  return std::isfinite(r) && r > 0.0f &&
         (scan.max_range <= 0.0f || r < scan.max_range);
}

PreparedScan::PreparedScan(const LaserScan& scan, const SsoOptions& options) {
  const double beta =
      options.beta > 0.0 ? options.beta : std::fabs(scan.angle_increment);
  const Eigen::Matrix2d Rs = rotation(scan.sensor_pose.theta);
  points_.reserve(scan.size());
  ranges_.reserve(scan.size());
  covs_.reserve(scan.size());
  for (size_t i = 0; i < scan.size(); ++i) {
    if (!is_valid_return(scan, i)) continue;
    const double r = scan.ranges[i];
    const double phi = scan.bearing(i);
    points_.push_back(
        scan.sensor_pose.transform({r * std::cos(phi), r * std::sin(phi)}));
    ranges_.push_back(r);
    const double sf = r * beta;
    Eigen::Matrix2d c =
        Rs * range_bearing_cov(r, phi, options.range_std, options.bearing_std) *
        Rs.transpose();
    c.diagonal().array() += sf * sf;
    covs_.push_back(c);
    max_var_ = std::max(max_var_, max_eigenvalue(c));
  }
  // The range-bearing covariance's eigenvalues are range_std^2 and
  // (r bearing_std)^2, plus (r beta)^2: at most floor + k r^2. k is taken
  // as the largest ratio actually present, so the bound holds exactly.
  var_floor_ = options.range_std * options.range_std;
  for (size_t i = 0; i < covs_.size(); ++i)
    var_per_range2_ = std::max(var_per_range2_, (max_eigenvalue(covs_[i]) - var_floor_) /
                                                    (ranges_[i] * ranges_[i]));
  origin_ = {scan.sensor_pose.x, scan.sensor_pose.y};
  grid_ = PointGrid(points_, 2.0 * options.delta);
}

double scan_match_ratio(const PreparedScan& a, const PoseGaussian& pose_a,
                        const PreparedScan& b, const PoseGaussian& pose_b,
                        const SsoOptions& options) {
  if (a.empty()) return 0.0;
  if (b.empty()) return 0.0;
  // A seen from B: moves A's robot-frame points into B's frame.
  const PoseGaussian q = relative_pose(pose_a, pose_b);
  size_t matched = 0;
  if (!options.use_probabilistic) {
    for (const Point2D& p : a.points())
      if (b.grid().any_within(q.mean.transform(p), options.delta)) ++matched;
  } else {
    const auto& bcov = b.point_covs();
    const PointComposer through_q(q);
    for (size_t i = 0; i < a.size(); ++i) {
      const Point2D& s = a.points()[i];
      const Point2D p = through_q.transform(s);
      Eigen::Matrix2d Cp = through_q.cov(s, a.point_covs()[i]);
      Cp.diagonal().array() += kVarianceFloor;
      // No point of B farther than this can pass the gate: d^2 >= |d|^2 /
      // lambda_max(Cp + Cb) and lambda_max(Cp + Cb) <= lambda_max(Cp) +
      // max_j lambda_max(Cb_j).
      const double lp = max_eigenvalue(Cp) + kVarianceFloor;
      double radius = std::sqrt(options.gate * (lp + b.max_point_var()));
      // Tighter, by range: a point of B at distance |d| from p lies at most
      // rho + |d| from B's sensor (rho = |p - sensor|), so lambda_max(Cb)
      // <= c0 + k (rho + |d|)^2, and |d|^2 / (lp + c0 + k (rho + |d|)^2)
      // grows with |d|: the gate fails beyond the root R of
      //   R^2 = gate (lp + c0 + k (rho + R)^2).
      const double g = options.gate, k = b.var_per_range2();
      if (g * k < 1.0) {
        // sqrt rather than std::hypot (a slow libm call per point): no
        // overflow to guard against at a scan's ranges.
        const double ox = p.x - b.sensor_origin().x, oy = p.y - b.sensor_origin().y;
        const double rho = std::sqrt(ox * ox + oy * oy);
        const double a0 = lp + b.var_floor();
        const double bh = g * k * rho;
        const double R =
            (bh + std::sqrt(bh * bh + (1.0 - g * k) * g * (a0 + k * rho * rho))) / (1.0 - g * k);
        radius = std::min(radius, R);
      }
      const double r2 = radius * radius;
      const bool hit =
          b.grid().any_near(p, radius, [&](const Point2D& bp, uint32_t j) {
            const Eigen::Vector2d d(p.x - bp.x, p.y - bp.y);
            if (d.squaredNorm() > r2) return false;
            return mahalanobis2(d, Cp + bcov[j]) <= options.gate;
          });
      if (hit) ++matched;
    }
  }
  return static_cast<double>(matched) / static_cast<double>(a.size());
}

double scan_sso(const PreparedScan& a, const PoseGaussian& pose_a,
                const PreparedScan& b, const PoseGaussian& pose_b,
                const SsoOptions& options) {
  return 0.5 * (scan_match_ratio(a, pose_a, b, pose_b, options) +
                scan_match_ratio(b, pose_b, a, pose_a, options));
}

double scan_sso(const LaserScan& a, const Pose2D& pose_a, const LaserScan& b,
                const Pose2D& pose_b, const SsoOptions& options) {
  return scan_sso(PreparedScan(a, options), PoseGaussian(pose_a),
                  PreparedScan(b, options), PoseGaussian(pose_b), options);
}

}  // namespace hmt::area

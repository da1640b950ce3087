#include "hmt/area/landmark_sso.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "hmt/area/scan_sso.h"

namespace hmt::area {
namespace {

// Squared Mahalanobis distance of eps = q (+) zb - za in the frame of A, where
// q is B seen from A.
double landmark_distance2(const PoseGaussian& q, const Landmark& za,
                          const Landmark& zb) {
  const Point2D pb{zb.mean.x(), zb.mean.y()};
  const Point2D p = q.mean.transform(pb);
  const Eigen::Vector2d eps(p.x - za.mean.x(), p.y - za.mean.y());
  Eigen::Matrix2d S = compose_point_cov(q, pb, zb.cov) + za.cov;
  S.diagonal().array() += kVarianceFloor;
  return mahalanobis2(eps, S);
}

bool descriptors_match(const Landmark& a, const Landmark& b,
                       const SsoOptions& options) {
  if (options.descriptor_threshold <= 0.0) return true;
  if (a.descriptor.empty() || b.descriptor.empty()) return true;
  if (a.descriptor.size() != b.descriptor.size()) return false;
  double d2 = 0.0;
  for (size_t k = 0; k < a.descriptor.size(); ++k) {
    const double d = static_cast<double>(a.descriptor[k]) - b.descriptor[k];
    d2 += d * d;
  }
  return d2 <= options.descriptor_threshold * options.descriptor_threshold;
}

}  // namespace

Landmark landmark_from_range_bearing(const Pose2D& sensor_pose, double range,
                                     double bearing, double range_std,
                                     double bearing_std) {
  Landmark l;
  const Point2D p = sensor_pose.transform(
      {range * std::cos(bearing), range * std::sin(bearing)});
  l.mean = Eigen::Vector2d(p.x, p.y);
  const Eigen::Matrix2d R = rotation(sensor_pose.theta);
  l.cov = R * range_bearing_cov(range, bearing, range_std, bearing_std) *
          R.transpose();
  return l;
}

size_t count_landmark_matches(const LandmarkObservation& a,
                              const PoseGaussian& pose_a,
                              const LandmarkObservation& b,
                              const PoseGaussian& pose_b,
                              const SsoOptions& options) {
  const auto& la = a.landmarks;
  const auto& lb = b.landmarks;
  if (la.empty() || lb.empty()) return 0;
  const PoseGaussian b_from_a = relative_pose(pose_b, pose_a);
  const PoseGaussian a_from_b = relative_pose(pose_a, pose_b);
  // Candidate pairs (distance, i, j) passing both tests.
  std::vector<std::tuple<double, size_t, size_t>> pairs;
  for (size_t i = 0; i < la.size(); ++i) {
    for (size_t j = 0; j < lb.size(); ++j) {
      if (!descriptors_match(la[i], lb[j], options)) continue;
      const double d2 = 0.5 * (landmark_distance2(b_from_a, la[i], lb[j]) +
                               landmark_distance2(a_from_b, lb[j], la[i]));
      if (d2 <= options.gate) pairs.emplace_back(d2, i, j);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<char> used_a(la.size(), 0), used_b(lb.size(), 0);
  size_t m = 0;
  for (const auto& [d2, i, j] : pairs) {
    if (used_a[i] || used_b[j]) continue;
    used_a[i] = used_b[j] = 1;
    ++m;
  }
  return m;
}

double landmark_sso(const LandmarkObservation& a, const PoseGaussian& pose_a,
                    const LandmarkObservation& b, const PoseGaussian& pose_b,
                    const SsoOptions& options) {
  const size_t n = a.landmarks.size() + b.landmarks.size();
  if (n == 0) return 0.0;
  const size_t m = count_landmark_matches(a, pose_a, b, pose_b, options);
  return 2.0 * static_cast<double>(m) / static_cast<double>(n);
}

}  // namespace hmt::area

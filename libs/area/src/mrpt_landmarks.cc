#include "hmt/area/mrpt_landmarks.h"

#include <mrpt/obs/CObservationBearingRange.h>

#include <cmath>

namespace hmt::area {

LandmarkObservation from_mrpt(const mrpt::obs::CObservationBearingRange& obs) {
  const auto& sp = obs.sensorLocationOnRobot;
  const Pose2D sensor_pose(sp.x(), sp.y(), sp.yaw());
  const Eigen::Matrix2d R = rotation(sensor_pose.theta);
  LandmarkObservation out;
  out.landmarks.reserve(obs.sensedData.size());
  for (const auto& m : obs.sensedData) {
    if (!std::isfinite(m.range) || !(m.range > 0.0f) || !std::isfinite(m.yaw))
      continue;
    if (!obs.validCovariances) {
      out.landmarks.push_back(landmark_from_range_bearing(
          sensor_pose, m.range, m.yaw, obs.sensor_std_range,
          obs.sensor_std_yaw));
      continue;
    }
    // Full (range, yaw) block of the measurement's covariance.
    Landmark l = landmark_from_range_bearing(sensor_pose, m.range, m.yaw, 0, 0);
    const double c = std::cos(m.yaw), s = std::sin(m.yaw);
    Eigen::Matrix2d J;
    J << c, -m.range * s, s, m.range * c;
    Eigen::Matrix2d S;
    S << m.covariance(0, 0), m.covariance(0, 1), m.covariance(1, 0),
        m.covariance(1, 1);
    l.cov = R * J * S * J.transpose() * R.transpose();
    out.landmarks.push_back(std::move(l));
  }
  return out;
}

}  // namespace hmt::area

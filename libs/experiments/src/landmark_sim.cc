#include "hmt/experiments/landmark_sim.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace hmt::experiments {

int LandmarkSimOptions::steps() const {
  return static_cast<int>(std::lround(path_length / step));
}

void LandmarkSimOptions::validate() const {
  auto fail = [](const std::string& what) {
    throw std::invalid_argument("landmark simulation: " + what);
  };
  if (landmarks < 1) fail("landmarks must be >= 1");
  if (!(path_length > 0.0)) fail("path_length must be > 0");
  if (!(step > 0.0) || step > path_length) fail("step must be in (0, path_length]");
  if (!(x_max > x_min)) fail("x_max must be > x_min");
  if (!(half_width > 0.0)) fail("half_width must be > 0");
  if (!(max_range > 0.0)) fail("max_range must be > 0");
  if (!(fov > 0.0) || fov > 2.0 * M_PI) fail("fov must be in (0, 2 pi]");
  if (!(range_std > 0.0) || !(bearing_std > 0.0))
    fail("sensor standard deviations must be > 0");
  if (!(odo_xy_std > 0.0) || !(odo_phi_std > 0.0))
    fail("odometry standard deviations must be > 0");
}

std::vector<RangeBearing> visible_landmarks(const std::vector<Point2D>& landmarks,
                                            const Pose2D& pose,
                                            double max_range, double fov) {
  std::vector<RangeBearing> out;
  const Pose2D inv = pose.inverse();
  for (size_t i = 0; i < landmarks.size(); ++i) {
    const Point2D p = inv.transform(landmarks[i]);
    const double r = std::hypot(p.x, p.y);
    if (r > max_range || r <= 0.0) continue;
    const double phi = std::atan2(p.y, p.x);
    if (std::fabs(phi) > 0.5 * fov) continue;
    out.push_back({static_cast<int>(i), r, phi});
  }
  return out;
}

LandmarkSim simulate_straight_path(const LandmarkSimOptions& o, Random& rng) {
  o.validate();
  LandmarkSim sim;
  sim.landmarks.reserve(o.landmarks);
  for (int i = 0; i < o.landmarks; ++i)
    sim.landmarks.push_back(
        {rng.uniform(o.x_min, o.x_max), rng.uniform(-o.half_width, o.half_width)});

  const int n = o.steps();
  sim.steps.reserve(n + 1);
  Pose2D pose;  // origin, heading +x
  for (int t = 0; t <= n; ++t) {
    SimStep s;
    if (t > 0) {
      const Pose2D motion(o.step, 0.0, 0.0);
      pose = pose + motion;
      s.odometry = Pose2D(motion.x + rng.normal(0.0, o.odo_xy_std),
                          motion.y + rng.normal(0.0, o.odo_xy_std),
                          wrap_angle(motion.theta + rng.normal(0.0, o.odo_phi_std)));
    }
    s.true_pose = pose;
    s.z = visible_landmarks(sim.landmarks, pose, o.max_range, o.fov);
    for (RangeBearing& m : s.z) {
      m.range += rng.normal(0.0, o.range_std);
      m.bearing = wrap_angle(m.bearing + rng.normal(0.0, o.bearing_std));
    }
    sim.steps.push_back(std::move(s));
  }
  return sim;
}

}  // namespace hmt::experiments

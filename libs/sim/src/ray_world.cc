#include "hmt/sim/ray_world.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace hmt::sim {

LaserScan raycast(const World& world, const Pose2D& robot, const Sensor& s,
                  Random* noise, double sigma) {
  if (s.beams < 2 || !(s.fov > 0.0) || s.fov > 2.0 * M_PI + 1e-9 || !(s.max_range > 0.0))
    throw std::invalid_argument("sim::raycast: bad sensor");
  LaserScan scan;
  const bool full_circle = s.fov >= 2.0 * M_PI - 1e-9;
  scan.angle_increment =
      static_cast<float>(full_circle ? s.fov / s.beams : s.fov / (s.beams - 1));
  scan.angle_min = static_cast<float>(-0.5 * s.fov);
  scan.max_range = static_cast<float>(s.max_range);
  scan.ranges.assign(s.beams, scan.max_range);
  scan.valid.assign(s.beams, 0);
  for (int i = 0; i < s.beams; ++i) {
    const double a = robot.theta + scan.bearing(i);
    const double dx = std::cos(a), dy = std::sin(a);
    double best = std::numeric_limits<double>::infinity();
    for (const Segment& w : world.walls) {
      // robot + t d = w0 + u (w1 - w0)
      const double ex = w.x1 - w.x0, ey = w.y1 - w.y0;
      const double den = dx * ey - dy * ex;
      if (std::fabs(den) < 1e-12) continue;
      const double qx = w.x0 - robot.x, qy = w.y0 - robot.y;
      const double t = (qx * ey - qy * ex) / den;
      const double u = (qx * dy - qy * dx) / den;
      if (t > s.min_hit && u >= 0.0 && u <= 1.0 && t < best) best = t;
    }
    if (best < s.max_range) {
      double r = best;
      if (noise) r += noise->normal(0.0, sigma);
      scan.ranges[i] = static_cast<float>(r);
      scan.valid[i] = 1;
    }
  }
  return scan;
}

}  // namespace hmt::sim

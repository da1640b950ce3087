// A 2D world of wall segments and a ray-casting range sensor with optional
// Gaussian range noise: the simulator behind the tests, benchmarks and
// experiments (the scenario worlds and routes live with their users).
#pragma once

#include <cmath>
#include <vector>

#include "hmt/common/pose2d.h"
#include "hmt/common/random.h"
#include "hmt/common/sensor_data.h"

namespace hmt::sim {

struct Segment {
  double x0, y0, x1, y1;
};

struct World {
  std::vector<Segment> walls;
  void wall(double x0, double y0, double x1, double y1) {
    walls.push_back({x0, y0, x1, y1});
  }
  // The outline of the axis-aligned box [x0, x1] x [y0, y1].
  void box(double x0, double y0, double x1, double y1) {
    wall(x0, y0, x1, y0);
    wall(x1, y0, x1, y1);
    wall(x1, y1, x0, y1);
    wall(x0, y1, x0, y0);
  }
};

struct Sensor {
  int beams = 360;
  double fov = 2.0 * M_PI;  // [rad], centred on the robot's heading
  double max_range = 20.0;  // [m]
  // A wall crossing counts only at a distance > min_hit [m]: the default
  // ignores a wall the sensor sits on; 0 keeps crossings a rounding error
  // away (the metric SLAM tests' robot drives along a wall of their office).
  double min_hit = 1e-9;
};

// Range scan from `robot` (sensor at the robot origin). Beam 0 is at bearing
// -fov/2 (the robot's right), bearings increase counter-clockwise by fov/beams
// for a full circle (no beam twice) and by fov/(beams - 1) otherwise (both
// edges of the field of view). A beam's range is the nearest wall crossing at
// a distance > min_hit; beams that hit nothing closer than max_range are invalid,
// with range max_range. With `noise`, each valid beam, in beam order, gets
// one draw of noise->normal(0, sigma) added to its range (invalid beams draw
// nothing). Throws std::invalid_argument for fewer than 2 beams, a field of
// view outside (0, 2 pi] or a non-positive max_range.
LaserScan raycast(const World& world, const Pose2D& robot, const Sensor& sensor,
                  Random* noise = nullptr, double sigma = 0.0);

}  // namespace hmt::sim

// A tiny 2D world of wall segments and a ray-casting range sensor, to make
// scan sequences with a known layout for the area tests and benchmarks.
#pragma once

#include <vector>

#include "hmt/area/keyframe.h"
#include "hmt/common/sensor_data.h"

namespace hmt::area::sim {

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
  double fov = 2.0 * M_PI;  // centred on the robot's heading
  double max_range = 20.0;
};

// Range scan from `robot` (sensor at the robot origin); beams that hit
// nothing within max_range are invalid.
LaserScan raycast(const World& world, const Pose2D& robot, const Sensor& s);

// Three 7 m x 6 m rooms in a row along x (x in [0, 21], y in [0, 6]) with
// 0.3 m thick walls, joined by 0.9 m doors at x = 7 (y in [4.6, 5.5]) and
// x = 14 (y in [0.5, 1.4]); a pillar in the middle of each room.
World three_rooms();

// Keyframes every `step` metres along `path` (heading along the path), each
// with a scan from `sensor`.
std::vector<Keyframe> walk(const World& world, const std::vector<Point2D>& path,
                           double step, const Sensor& sensor);

// A loop around the pillar of each room in turn, passing both doors, with a
// 360-degree 360-beam scanner.
std::vector<Keyframe> three_rooms_walk(double step = 0.3);
// The room (0, 1, 2) a pose is in.
int room_of(const Pose2D& p);

// A straight corridor 2.4 m wide and `length` metres long along x, with a
// 1 m wide, 1.5 m deep alcove every 4 m on alternating sides.
World corridor(double length);

// Keyframes along the corridor's axis every `step` metres, heading +x, with
// a front 180-degree, 361-beam scanner of 20 m range.
std::vector<Keyframe> corridor_walk(double length, double step);

}  // namespace hmt::area::sim

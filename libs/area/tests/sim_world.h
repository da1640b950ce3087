// Scan sequences with a known layout for the area tests and benchmarks, in
// worlds of wall segments seen by the ray-casting sensor of hmt_sim.
#pragma once

#include <vector>

#include "hmt/area/keyframe.h"
#include "hmt/common/sensor_data.h"
#include "hmt/sim/ray_world.h"

namespace hmt::area::sim {

// The world, the sensor and the ray caster are the shared simulator's.
using hmt::sim::Segment;
using hmt::sim::Sensor;
using hmt::sim::World;
using hmt::sim::raycast;

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

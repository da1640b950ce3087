// A building-like 2D world of wall segments, a ray-casting range sensor of
// any field of view, and keyframes along a route through it: the simulated
// data of the field-of-view experiment (000 Sec. 6.2).
//
// The world and the ray caster are the shared simulator's (hmt_sim); the
// building, the route and the turn-in-place keyframes are this experiment's.
#pragma once

#include <string>
#include <vector>

#include "hmt/area/keyframe.h"
#include "hmt/common/pose2d.h"
#include "hmt/common/sensor_data.h"
#include "hmt/sim/ray_world.h"

namespace hmt::experiments {

using sim::Segment;
using sim::World;

struct RangeSensor {
  std::string name;
  double fov = 2.0 * M_PI;  // [rad], centred on the robot's heading
  int beams = 720;
  double max_range = 20.0;  // [m]

  sim::Sensor sensor() const { return {beams, fov, max_range}; }
};

// The three sensors of 000 Sec. 6.2 with one beam per half degree: a
// 360-degree pair of scanners, a 180-degree front scanner and a 65-degree
// field of view like the paper's stereo camera; all of `max_range`.
std::vector<RangeSensor> standard_sensors(double max_range = 20.0);

// Range scan from `robot` (sensor at the robot origin); beams that hit
// nothing within max_range are invalid (sim::raycast; throws
// std::invalid_argument naming the sensor if it is not a valid one).
LaserScan raycast(const World& world, const Pose2D& robot, const RangeSensor& s);

// A building of 40 m x 20 m: an east-west corridor 2.5 m wide (y in
// [8.5, 11]) with four rooms south of it and three north, each joined to the
// corridor by a 1.2 m door, plus a few pieces of furniture; walls 0.3 m thick
// (a zero-thickness wall would let both sides' scans match point for point).
World building();
// A route through it: along the corridor with a loop through every room,
// then back along the corridor to the start (places revisited with the
// opposite heading, which a narrow sensor sees as different places).
std::vector<Point2D> building_route();

// A small world for quick checks: two 6 m x 6 m rooms either side of a 2 m
// corridor, and a route through both and back.
World two_rooms();
std::vector<Point2D> two_rooms_route();

// Robot poses along `route`: one every `step` metres driven (heading along
// the segment) and, at a corner, turning in place, one every `turn_step`
// radians of the turn (the keyframe policy of a mapper that adds a keyframe
// after a translation or a rotation threshold).
std::vector<Pose2D> route_poses(const std::vector<Point2D>& route, double step,
                                double turn_step);

// Keyframes at `poses` (exact poses) with a scan of `sensor` each.
std::vector<area::Keyframe> simulate_keyframes(const World& world,
                                               const std::vector<Pose2D>& poses,
                                               const RangeSensor& sensor);

}  // namespace hmt::experiments

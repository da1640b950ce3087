#include "hmt/experiments/building_sim.h"

#include <cmath>
#include <stdexcept>
#include <utility>

namespace hmt::experiments {
namespace {

constexpr double kWall = 0.3;  // wall thickness [m]

// A horizontal wall of thickness kWall over [x0, x1] whose lower face is at
// y, with door openings [centre - width/2, centre + width/2].
void horizontal_wall(World& w, double x0, double x1, double y,
                     const std::vector<double>& doors, double width) {
  double from = x0;
  for (double c : doors) {
    w.box(from, y, c - 0.5 * width, y + kWall);
    from = c + 0.5 * width;
  }
  w.box(from, y, x1, y + kWall);
}

// A vertical wall of thickness kWall centred on x over [y0, y1].
void vertical_wall(World& w, double x, double y0, double y1) {
  w.box(x - 0.5 * kWall, y0, x + 0.5 * kWall, y1);
}

}  // namespace

std::vector<RangeSensor> standard_sensors(double max_range) {
  return {{"360deg", 2.0 * M_PI, 720, max_range},
          {"180deg", M_PI, 361, max_range},
          {"65deg", 65.0 * M_PI / 180.0, 131, max_range}};
}

LaserScan raycast(const World& world, const Pose2D& robot, const RangeSensor& s) {
  if (s.beams < 2 || !(s.fov > 0.0) || s.fov > 2.0 * M_PI + 1e-9 || !(s.max_range > 0.0))
    throw std::invalid_argument("raycast: bad sensor '" + s.name + "'");
  return sim::raycast(world, robot, s.sensor());
}

World building() {
  World w;
  const double W = 40.0, H = 20.0, t = kWall;
  // Outer walls.
  w.box(-t, -t, W + t, 0);
  w.box(-t, H, W + t, H + t);
  w.box(-t, 0, 0, H);
  w.box(W, 0, W + t, H);
  // Corridor y in [8.5, 11]: its south wall (faces 8.2 .. 8.5) and north
  // wall (11 .. 11.3), with one 1.2 m door per room.
  horizontal_wall(w, 0, W, 8.5 - t, {3.0, 16.0, 23.0, 36.0}, 1.2);
  horizontal_wall(w, 0, W, 11.0, {5.0, 20.0, 34.0}, 1.2);
  // Room partitions: south rooms split at x = 10, 20, 30; north at 13, 27.
  for (double x : {10.0, 20.0, 30.0}) vertical_wall(w, x, 0, 8.5 - t);
  for (double x : {13.0, 27.0}) vertical_wall(w, x, 11.0 + t, H);
  // Furniture, inside each room's loop of the route.
  w.box(4.5, 3.0, 6.5, 4.5);
  w.box(13.5, 3.0, 16.5, 4.5);
  w.box(24.0, 3.0, 26.0, 5.0);
  w.box(33.0, 3.0, 36.0, 4.5);
  w.box(7.0, 15.0, 9.0, 16.5);
  w.box(18.0, 15.0, 22.0, 16.5);
  w.box(32.0, 15.0, 35.0, 16.5);
  return w;
}

std::vector<Point2D> building_route() {
  const double c = 9.75;  // corridor axis
  return {
      {1.5, c},
      // South room 1 (door x = 3).
      {3, c}, {3, 6.5}, {8.5, 6.5}, {8.5, 1.5}, {1.5, 1.5}, {1.5, 6.5}, {3, 6.5}, {3, c},
      // North room 1 (door x = 5).
      {5, c}, {5, 13}, {11.5, 13}, {11.5, 18.5}, {1.5, 18.5}, {1.5, 13}, {5, 13}, {5, c},
      // South room 2 (door x = 16).
      {16, c}, {16, 6.5}, {18.5, 6.5}, {18.5, 1.5}, {11.5, 1.5}, {11.5, 6.5}, {16, 6.5}, {16, c},
      // North room 2 (door x = 20).
      {20, c}, {20, 13}, {25.5, 13}, {25.5, 18.5}, {14.5, 18.5}, {14.5, 13}, {20, 13}, {20, c},
      // South room 3 (door x = 23).
      {23, c}, {23, 6.5}, {28.5, 6.5}, {28.5, 1.5}, {21.5, 1.5}, {21.5, 6.5}, {23, 6.5}, {23, c},
      // North room 3 (door x = 34).
      {34, c}, {34, 13}, {38.5, 13}, {38.5, 18.5}, {28.5, 18.5}, {28.5, 13}, {34, 13}, {34, c},
      // South room 4 (door x = 36).
      {36, c}, {36, 6.5}, {38.5, 6.5}, {38.5, 1.5}, {31.5, 1.5}, {31.5, 6.5}, {36, 6.5}, {36, c},
      // To the east end, and back along the corridor to the start.
      {38.5, c}, {1.5, c}};
}

World two_rooms() {
  World w;
  const double t = kWall;
  w.box(-t, -t, 6 + t, 0);
  w.box(-t, 14, 6 + t, 14 + t);
  w.box(-t, 0, 0, 14);
  w.box(6, 0, 6 + t, 14);
  horizontal_wall(w, 0, 6, 6.0 - t, {3.0}, 1.2);  // south room y in [0, 5.7]
  horizontal_wall(w, 0, 6, 8.0, {3.0}, 1.2);      // north room y in [8.3, 14]
  w.box(2.5, 2.0, 3.5, 3.0);
  w.box(2.5, 11.0, 3.5, 12.0);
  return w;
}

std::vector<Point2D> two_rooms_route() {
  return {{1.0, 7.0}, {3, 7}, {3, 4.5}, {5, 4.5}, {5, 1}, {1, 1}, {1, 4.5},
          {3, 4.5}, {3, 7}, {3, 9.5}, {5, 9.5}, {5, 13}, {1, 13}, {1, 9.5},
          {3, 9.5}, {3, 7}, {5, 7}};
}

std::vector<Pose2D> route_poses(const std::vector<Point2D>& route, double step,
                                double turn_step) {
  if (!(step > 0.0) || !(turn_step > 0.0))
    throw std::invalid_argument("route_poses: step and turn_step must be > 0");
  std::vector<Pose2D> out;
  double t0 = 0.0;  // distance into the next segment of its first keyframe
  double prev_heading = 0.0;
  bool first = true;
  for (size_t k = 0; k + 1 < route.size(); ++k) {
    const Point2D a = route[k], b = route[k + 1];
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    if (len <= 0.0) continue;
    const double heading = std::atan2(b.y - a.y, b.x - a.x);
    if (!first) {
      // Turn in place at `a`, one keyframe per turn_step of rotation.
      const double turn = wrap_angle(heading - prev_heading);
      const double sign = turn < 0 ? -1.0 : 1.0;
      bool turned = false;
      for (int j = 1; j * turn_step < std::fabs(turn) - 1e-9; ++j) {
        out.emplace_back(a.x, a.y, wrap_angle(prev_heading + sign * j * turn_step));
        turned = true;
      }
      if (turned) t0 = step;  // the next translation keyframe after `step`
    }
    double t = t0;
    for (; t < len - 1e-9; t += step)
      out.emplace_back(a.x + (b.x - a.x) * t / len, a.y + (b.y - a.y) * t / len,
                       heading);
    t0 = t - len;
    prev_heading = heading;
    first = false;
  }
  return out;
}

std::vector<area::Keyframe> simulate_keyframes(const World& world,
                                               const std::vector<Pose2D>& poses,
                                               const RangeSensor& sensor) {
  std::vector<area::Keyframe> out;
  out.reserve(poses.size());
  for (const Pose2D& p : poses) {
    area::Keyframe kf;
    kf.pose.mean = p;
    kf.scan = raycast(world, p, sensor);
    out.push_back(std::move(kf));
  }
  return out;
}

}  // namespace hmt::experiments

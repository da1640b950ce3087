#include "sim_world.h"

#include <cmath>
#include <utility>

namespace hmt::area::sim {

World three_rooms() {
  // Walls 0.3 m thick: a wall seen from both sides must not look like one
  // surface (a zero-thickness wall would match the two rooms' scans point for
  // point along it).
  World w;
  const double t = 0.3;
  w.box(-t, -t, 21 + t, 0);
  w.box(-t, 6, 21 + t, 6 + t);
  w.box(-t, 0, 0, 6);
  w.box(21, 0, 21 + t, 6);
  // Doors out of line, so that no ray crosses both: x = 7, y in [4.6, 5.5]
  // and x = 14, y in [0.5, 1.4].
  w.box(7 - t / 2, 0, 7 + t / 2, 4.6);
  w.box(7 - t / 2, 5.5, 7 + t / 2, 6);
  w.box(14 - t / 2, 0, 14 + t / 2, 0.5);
  w.box(14 - t / 2, 1.4, 14 + t / 2, 6);
  // A pillar in each room.
  for (double cx : {3.5, 10.5, 17.5}) w.box(cx - 0.3, 2.7, cx + 0.3, 3.3);
  return w;
}

std::vector<Keyframe> walk(const World& world, const std::vector<Point2D>& path,
                           double step, const Sensor& sensor) {
  std::vector<Keyframe> out;
  double carry = 0.0;  // distance along the segment to the next keyframe
  for (size_t k = 0; k + 1 < path.size(); ++k) {
    const Point2D a = path[k], b = path[k + 1];
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    const double heading = std::atan2(b.y - a.y, b.x - a.x);
    double t = carry;
    for (; t < len; t += step) {
      Keyframe kf;
      kf.pose.mean = Pose2D(a.x + (b.x - a.x) * t / len,
                            a.y + (b.y - a.y) * t / len, heading);
      kf.scan = raycast(world, kf.pose.mean, sensor);
      out.push_back(std::move(kf));
    }
    carry = t - len;
  }
  return out;
}

std::vector<Keyframe> three_rooms_walk(double step) {
  Sensor s;
  s.beams = 360;
  s.fov = 2.0 * M_PI;
  s.max_range = 20.0;
  // A loop around each room's pillar, then through the door to the next.
  const std::vector<Point2D> path = {
      {1.5, 1.5},  {5.5, 1.5},   {5.5, 4.5},   {1.5, 4.5},  {1.5, 2.5},
      {5.5, 5.05}, {8.5, 5.05},  {12.5, 4.5},  {12.5, 1.5}, {8.5, 1.5},
      {8.5, 3.5},  {12.5, 0.95}, {15.5, 0.95}, {19.5, 1.5}, {19.5, 4.5},
      {15.5, 4.5}, {15.5, 2.5}};
  return walk(three_rooms(), path, step, s);
}

int room_of(const Pose2D& p) { return p.x < 7.0 ? 0 : p.x < 14.0 ? 1 : 2; }

World corridor(double length) {
  World w;
  const double y0 = 0.0, y1 = 2.4, door = 1.0, depth = 1.5;
  // Walls with a gap every 4 m, alternating sides, each gap an alcove.
  double xb = 0.0, xt = 0.0;
  int k = 0;
  for (double x = 2.0; x + door < length; x += 4.0, ++k) {
    if (k % 2 == 0) {
      w.wall(xb, y0, x, y0);
      w.wall(x, y0, x, y0 - depth);
      w.wall(x, y0 - depth, x + door, y0 - depth);
      w.wall(x + door, y0 - depth, x + door, y0);
      xb = x + door;
    } else {
      w.wall(xt, y1, x, y1);
      w.wall(x, y1, x, y1 + depth);
      w.wall(x, y1 + depth, x + door, y1 + depth);
      w.wall(x + door, y1 + depth, x + door, y1);
      xt = x + door;
    }
  }
  w.wall(xb, y0, length, y0);
  w.wall(xt, y1, length, y1);
  w.wall(0, y0, 0, y1);
  w.wall(length, y0, length, y1);
  return w;
}

std::vector<Keyframe> corridor_walk(double length, double step) {
  Sensor s;
  s.beams = 361;
  s.fov = M_PI;
  s.max_range = 20.0;
  return walk(corridor(length), {{0.5, 1.2}, {length - 0.5, 1.2}}, step, s);
}

}  // namespace hmt::area::sim

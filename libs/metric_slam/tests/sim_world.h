// A tiny simulated world for tests: walls as line segments, ray casting by
// hmt_sim, a robot driven along way-points, noisy odometry.
#pragma once

#include <cmath>
#include <vector>

#include "hmt/common/random.h"
#include "hmt/common/sensor_data.h"
#include "hmt/sim/ray_world.h"

namespace hmt::testing_sim {

using Segment = sim::Segment;

// A 20 x 10 m room with an inner wall and a few boxes (not symmetric, so
// scan matching is well constrained).
inline std::vector<Segment> office_world() {
  std::vector<Segment> w = {{0, 0, 20, 0}, {20, 0, 20, 10}, {20, 10, 0, 10},
                            {0, 10, 0, 0},  {8, 0, 8, 6},    {8, 6, 9, 6},
                            {9, 6, 9, 0}};
  auto box = [&](double x, double y, double s) {
    w.push_back({x, y, x + s, y});
    w.push_back({x + s, y, x + s, y + s});
    w.push_back({x + s, y + s, x, y + s});
    w.push_back({x, y + s, x, y});
  };
  box(3, 7, 0.8);
  box(14, 2, 1.2);
  box(16.5, 7.5, 0.6);
  box(11, 8, 0.5);
  return w;
}

// A long corridor with niches every few metres: each scan sees only a short
// stretch of it, as in a large building.
inline std::vector<Segment> corridor_world(double length = 60.0) {
  std::vector<Segment> w = {{0, 0, length, 0}, {0, 3, length, 3}, {0, 0, 0, 3},
                            {length, 0, length, 3}};
  for (int k = 0; 5.0 * k + 3.5 < length; ++k) {
    const double x = 2.0 + 5.0 * k + 0.7 * (k % 3);
    const double y = (k % 2) ? 3.0 : 0.0, d = (k % 2) ? -0.4 : 0.4;
    w.push_back({x, y, x, y + d});
    w.push_back({x, y + d, x + 0.6, y + d});
    w.push_back({x + 0.6, y + d, x + 0.6, y});
  }
  return w;
}

// A street: building fronts 18-40 m either side with gaps between them, and
// small trees along both kerbs 6 m from the centre line. Seen within 20 m,
// a scan holds the trees and little else.
inline std::vector<Segment> street_world(uint64_t seed) {
  Random rng(seed);
  std::vector<Segment> w;
  for (double side : {-1.0, 1.0})
    for (double x = -40.0; x < 260.0;) {
      const double len = rng.uniform(12.0, 40.0), y = side * rng.uniform(18.0, 40.0);
      w.push_back({x, y, x + len, y});
      w.push_back({x, y, x, y + side * 8.0});
      w.push_back({x + len, y, x + len, y + side * 8.0});
      x += len + rng.uniform(4.0, 15.0);
    }
  for (double side : {-1.0, 1.0})
    for (double x = -20.0; x < 240.0; x += rng.uniform(8.0, 16.0)) {
      const double cx = x, cy = side * 6.0 + rng.normal(0.0, 0.5), r = 0.25;
      for (int k = 0; k < 6; ++k) {
        const double a = k * M_PI / 3.0, b = (k + 1) * M_PI / 3.0;
        w.push_back({cx + r * std::cos(a), cy + r * std::sin(a), cx + r * std::cos(b),
                     cy + r * std::sin(b)});
      }
    }
  return w;
}

// A scan of `beams` beams over `fov` (< 2 pi) centred on the heading (beam 0
// on the right), ranges to max_range, each valid range with N(0, sigma) noise
// from `noise` if given: hmt_sim's ray caster, counting wall crossings at any
// distance > 0 (the loop of the tests drives along a box's edge).
inline LaserScan cast_scan(const std::vector<Segment>& world, const Pose2D& pose,
                           int beams, double fov, double max_range, Random* noise,
                           double sigma) {
  sim::Sensor s;
  s.beams = beams;
  s.fov = fov;
  s.max_range = max_range;
  s.min_hit = 0.0;
  return sim::raycast(sim::World{world}, pose, s, noise, sigma);
}

struct SimRun {
  std::vector<Pose2D> truth;
  Log log;
};

// Drives through the way-points at `step` metres per scan, with odometry
// noise proportional to the motion.
inline SimRun simulate(const std::vector<Pose2D>& waypoints, double step,
                       uint64_t seed, double odo_noise = 0.05,
                       const std::vector<Segment>& world = office_world(),
                       double max_range = 30.0) {
  Random rng(seed);
  SimRun run;
  Pose2D pose = waypoints.front();
  Pose2D prev = pose;
  auto emit = [&](bool first) {
    LogStep st;
    st.timestamp = static_cast<double>(run.truth.size());
    st.scan = cast_scan(world, pose, 181, M_PI, max_range, &rng, 0.01);
    st.scan.timestamp = st.timestamp;
    if (!first) {
      const Pose2D u = pose - prev;
      const double d = u.norm();
      st.odometry_increment = Pose2D(u.x + rng.normal(0, odo_noise * d),
                                     u.y + rng.normal(0, odo_noise * d),
                                     u.theta + rng.normal(0, odo_noise * (d + std::fabs(u.theta))));
      st.has_odometry = true;
    }
    run.truth.push_back(pose);
    run.log.steps.push_back(st);
    prev = pose;
  };
  emit(true);
  for (size_t k = 1; k < waypoints.size(); ++k) {
    const Pose2D& target = waypoints[k];
    for (;;) {
      const double dx = target.x - pose.x, dy = target.y - pose.y;
      const double dist = std::hypot(dx, dy);
      if (dist < 1e-9) break;
      const double heading = std::atan2(dy, dx);
      const double adv = std::min(step, dist);
      pose = Pose2D(pose.x + adv * std::cos(heading), pose.y + adv * std::sin(heading),
                    heading);
      emit(false);
    }
  }
  return run;
}

// The pose reached from truth[first - 1] by the odometry of steps
// first..last (by default the whole run, from its first pose).
inline Pose2D dead_reckoning(const SimRun& run, size_t first = 1, size_t last = 0) {
  if (last == 0) last = run.log.steps.size() - 1;
  Pose2D p = run.truth.at(first - 1);
  for (size_t i = first; i <= last; ++i) p = p + run.log.steps.at(i).odometry_increment;
  return p;
}

// Steps first..last of the run keep only every `keep`-th beam's return
// (0: none): open ground outdoors, where a scan holds a few trees or none.
inline SimRun with_sparse_scans(SimRun run, size_t first, size_t last, size_t keep) {
  for (size_t i = first; i <= last; ++i) {
    LaserScan& s = run.log.steps.at(i).scan;
    for (size_t b = 0; b < s.size(); ++b)
      if (keep == 0 || b % keep != 0) {
        s.ranges[b] = s.max_range;
        s.valid[b] = 0;
      }
  }
  return run;
}

}  // namespace hmt::testing_sim

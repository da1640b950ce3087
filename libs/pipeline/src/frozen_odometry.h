// A log whose odometry stands still while its laser sees the robot move:
// frozen wheel encoders, an odometry field the recorder left at zero, a
// laser-only log written with a constant pose. The filter processes a scan
// only once the odometry has moved ([metric_slam] update_distance /
// update_angle), and each new scan's match starts from the odometry, so such
// a log would end as a map of its first scans and a trajectory standing
// still, with exit code 0: a silently wrong result. This check refuses it,
// naming the step.
//
// The rule: while the odometry has moved the robot less than kStillDistance
// and kStillAngle since a scan (the reference), a later scan sees the same
// scene, less what moves in it (people, a door, a passing car). When more
// than kChangedShare of the beams that return in both changed by more than
// kChangedRange (plus kChangedRangeShare of the range), the scene is no
// longer the reference's: the robot moved and its odometry did not. Where
// the odometry moves, the reference is the latest scan, so a log with
// working odometry is never compared across a real motion: on the nine
// shared logs and the simulated office and campus the odometry moves more
// than that between every two scans, so no scan is compared at all. The
// same logs with the odometry set to zero fail at steps 1-8, Intel with its
// odometry frozen from step 401 on at step 402.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "hmt/common/sensor_data.h"

namespace hmt::pipeline {

class FrozenOdometryCheck {
 public:
  static constexpr double kStillDistance = 0.01;   // m
  static constexpr double kStillAngle = 0.01;      // rad
  static constexpr double kChangedRange = 0.5;     // m
  static constexpr double kChangedRangeShare = 0.05;
  static constexpr double kChangedShare = 0.75;
  static constexpr size_t kMinBeams = 20;  // fewer returning in both: no verdict

  // The next step of the log, `index` its place in the log (for the
  // message). Throws InputError when the step's scan shows the robot moved
  // while the odometry stood still.
  void add(const LogStep& step, size_t index, const std::string& source);

 private:
  // The share of the beams returning in both scans whose ranges differ by
  // more than the tolerance; negative when fewer than kMinBeams return in
  // both (or the beam counts differ).
  static double changed_share(const LaserScan& a, const LaserScan& b);

  bool have_reference_ = false;
  LaserScan reference_;
  size_t reference_index_ = 0;
  Pose2D moved_;  // the odometry since the reference
};

}  // namespace hmt::pipeline

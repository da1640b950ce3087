// The odometry motion model: the measured increment u, corrupted by zero-mean
// Gaussian noise in the previous robot frame whose standard deviations grow
// with the distance and the turn (the srr/srt/str/stt model of GMapping).
#pragma once

#include "hmt/common/config.h"
#include "hmt/common/pose2d.h"
#include "hmt/common/random.h"

namespace hmt::metric_slam {

struct MotionOptions {
  double srr = 0.1;   // translation std dev per metre travelled
  double srt = 0.2;   // translation std dev per radian turned (m/rad)
  double str = 0.1;   // rotation std dev per metre travelled (rad/m)
  double stt = 0.2;   // rotation std dev per radian turned
  double min_sigma_xy = 0.01;     // m
  double min_sigma_theta = 0.01;  // rad

  void load(Config& cfg, const std::string& section = "motion_model");
};

struct MotionSigmas {
  double xy, theta;
};

class MotionModel {
 public:
  explicit MotionModel(const MotionOptions& opt) : opt_(opt) {}
  MotionSigmas sigmas(const Pose2D& u) const;
  // The part of sigmas(u).xy that grows with the distance travelled,
  // min_sigma_xy + srr |u|: how far the step may have carried the robot
  // from where its odometry says, which the scan match must reach.
  double distance_sigma(const Pose2D& u) const;
  Pose2D sample(const Pose2D& prev, const Pose2D& u, Random& rng) const;
  // log p(x | prev, u) up to a constant that depends only on u.
  double log_density(const Pose2D& prev, const Pose2D& u, const Pose2D& x) const;

 private:
  MotionOptions opt_;
};

}  // namespace hmt::metric_slam

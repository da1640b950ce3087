// Simulated range-bearing landmark SLAM data for the information-loss
// experiment of 000 Sec. 6.1: a robot drives a straight path through a field
// of point landmarks placed uniformly at random, with noisy odometry and a
// range-bearing sensor that identifies the landmarks it sees.
//
// What the paper fixes: a straight path of 50 m, 60 point features uniformly
// distributed, new random positions every run, odometry integrated. What it
// leaves open, and the values chosen here:
//  - geometry, from MRPT's landmark simulator and its EKF-SLAM demo
//    configuration (simul_landmarks_demo_EKF-SLAM.ini; the paper's experiments
//    were made with MRPT): 0.2 m between observations (250 motions for 50 m),
//    a 180-degree sensor of 6 m range; landmarks in a band 5 m either side of
//    the path over its length;
//  - noise: sigma_r = 0.1 m and sigma_phi = 2 deg for the sensor, 0.01 m per
//    axis and 0.1 deg per 0.2 m step for the odometry. The noise sets the
//    scale of e: it was chosen so that the fixed-size partitions lose what the
//    paper reports for them (about 1-3 %). With the demo configuration's much
//    finer sensor (0.01 m, 0.1 deg) and coarser odometry (0.04 m per step)
//    each pose is pinned by its landmarks, the information between landmarks
//    never observed together all but vanishes, and every e is below 0.02 %.
#pragma once

#include <cstdint>
#include <vector>

#include "hmt/common/pose2d.h"
#include "hmt/common/random.h"

namespace hmt::experiments {

struct LandmarkSimOptions {
  int landmarks = 60;
  double path_length = 50.0;  // [m], straight along +x from the origin
  double step = 0.2;          // [m] driven between two observations
  // Landmarks uniform in [x_min, x_max] x [-half_width, half_width].
  double x_min = 0.0;
  double x_max = 50.0;
  double half_width = 5.0;
  // Range-bearing sensor at the robot origin, looking along its heading.
  double max_range = 6.0;           // [m]
  double fov = M_PI;                // [rad], centred on the heading
  double range_std = 0.1;                   // [m]
  double bearing_std = 2.0 * M_PI / 180.0;  // [rad]
  // Odometry noise per step, in the frame of the increment.
  double odo_xy_std = 0.01;                  // [m]
  double odo_phi_std = 0.1 * M_PI / 180.0;   // [rad]

  int steps() const;  // number of motions: round(path_length / step)
  // Throws std::invalid_argument naming the first invalid field.
  void validate() const;
};

struct RangeBearing {
  int id = -1;          // landmark index in LandmarkSim::landmarks
  double range = 0.0;   // [m]
  double bearing = 0.0; // [rad], in (-pi, pi]
};

struct SimStep {
  Pose2D true_pose;
  // Noisy odometry reading of the motion since the previous step (zero for
  // the first step, taken before the robot moves).
  Pose2D odometry;
  std::vector<RangeBearing> z;  // by increasing landmark id
};

struct LandmarkSim {
  std::vector<Point2D> landmarks;  // true positions
  std::vector<SimStep> steps;      // steps() + 1 observations
};

// Landmarks, true path, odometry and observations, all drawn from `rng`.
LandmarkSim simulate_straight_path(const LandmarkSimOptions& options,
                                   Random& rng);

// The noise-free measurements of `landmarks` from `pose` (visibility test of
// the simulator: range <= max_range, |bearing| <= fov / 2).
std::vector<RangeBearing> visible_landmarks(const std::vector<Point2D>& landmarks,
                                            const Pose2D& pose,
                                            double max_range, double fov);

}  // namespace hmt::experiments

// A compact EKF for 2D range-bearing landmark SLAM with known data
// association (Dissanayake et al. 2001; the "simple EKF" of 000 Sec. 6.1).
//
// State: robot pose (x, y, theta) followed by the (x, y) of every landmark in
// the order they were first seen; one dense joint covariance.
//  - predict(): x <- x (+) u for an odometry increment u whose Gaussian noise
//    is given in the increment's frame (as MRPT's CActionRobotMovement2D):
//    P_rr <- F_x P_rr F_x^T + F_u Q F_u^T, P_rl <- F_x P_rl.
//  - update(): one batch update with every re-observed landmark, then each
//    landmark seen for the first time is appended through the inverse
//    observation model (its cross-covariances from the robot's).
// The same models as MRPT's CRangeBearingKFSLAM2D (a test checks that both
// give the same covariance on the same data), which is not used directly
// because this experiment needs thousands of filter runs in parallel threads
// and MRPT's class wants its data wrapped in per-step sensory-frame and
// action objects; this one works on plain vectors.
#pragma once

#include <Eigen/Core>
#include <unordered_map>
#include <vector>

#include "hmt/common/pose2d.h"
#include "hmt/experiments/landmark_sim.h"

namespace hmt::experiments {

struct EkfNoise {
  double range_std = 0.1;                   // [m]
  double bearing_std = 2.0 * M_PI / 180.0;  // [rad]
};

class EkfSlam2D {
 public:
  static constexpr int kVehicleSize = 3;

  explicit EkfSlam2D(const EkfNoise& noise);

  // Motion by the odometry increment u with covariance Q (in u's frame).
  void predict(const Pose2D& u, const Eigen::Matrix3d& Q);
  // Measurements with known landmark ids (ids >= 0; at most one per id).
  void update(const std::vector<RangeBearing>& z);

  Pose2D pose() const;
  Eigen::Matrix3d pose_cov() const { return P_.topLeftCorner<3, 3>(); }
  int landmark_count() const { return static_cast<int>(ids_.size()); }
  // Landmark ids in state order.
  const std::vector<int>& landmark_ids() const { return ids_; }
  // State index k of the landmark with this id, or -1.
  int index_of(int id) const;
  Eigen::Vector2d landmark(int k) const { return x_.segment<2>(3 + 2 * k); }
  Eigen::Matrix2d landmark_cov(int k) const {
    return P_.block<2, 2>(3 + 2 * k, 3 + 2 * k);
  }
  const Eigen::VectorXd& state() const { return x_; }
  const Eigen::MatrixXd& covariance() const { return P_; }

 private:
  void add_landmark(const RangeBearing& m);

  EkfNoise noise_;
  Eigen::VectorXd x_;
  Eigen::MatrixXd P_;
  std::vector<int> ids_;
  std::unordered_map<int, int> index_;
};

// Runs the filter over a simulation: the first step is an update only, every
// later one a prediction with the step's odometry (covariance diag(odo_xy^2,
// odo_xy^2, odo_phi^2)) and then an update. The filter's noise model is the
// simulator's. If `poses` is not null it receives the estimated pose and its
// marginal covariance after each step's update.
struct PoseEstimate {
  Pose2D mean;
  Eigen::Matrix3d cov;
};
EkfSlam2D run_ekf(const LandmarkSim& sim, const LandmarkSimOptions& options,
                  std::vector<PoseEstimate>* poses = nullptr);

}  // namespace hmt::experiments

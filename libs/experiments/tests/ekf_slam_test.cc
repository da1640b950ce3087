#include "hmt/experiments/ekf_slam.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>

namespace hmt::experiments {
namespace {

TEST(experiments_Ekf, NewLandmarkGetsTheInverseObservationModel) {
  const EkfNoise noise{0.05, 0.01};
  EkfSlam2D ekf(noise);
  ekf.update({{7, 4.0, M_PI / 2}});  // straight to the left, robot exactly known
  ASSERT_EQ(ekf.landmark_count(), 1);
  EXPECT_EQ(ekf.index_of(7), 0);
  EXPECT_EQ(ekf.index_of(3), -1);
  EXPECT_NEAR(ekf.landmark(0).x(), 0.0, 1e-12);
  EXPECT_NEAR(ekf.landmark(0).y(), 4.0, 1e-12);
  // Range noise along y, bearing noise (r * sigma_phi) along x.
  const Eigen::Matrix2d C = ekf.landmark_cov(0);
  EXPECT_NEAR(C(0, 0), std::pow(4.0 * 0.01, 2), 1e-12);
  EXPECT_NEAR(C(1, 1), 0.05 * 0.05, 1e-12);
  EXPECT_NEAR(C(0, 1), 0.0, 1e-12);
  EXPECT_TRUE(ekf.covariance().topRows<3>().isZero(0.0));
}

TEST(experiments_Ekf, PredictionComposesAndRotatesTheNoise) {
  EkfSlam2D ekf({0.05, 0.01});
  Eigen::Matrix3d Q = Eigen::Vector3d(0.04, 0.01, 0.0025).asDiagonal();
  ekf.predict(Pose2D(0, 0, M_PI / 2), Eigen::Matrix3d::Zero());
  ekf.predict(Pose2D(1.0, 0.0, 0.0), Q);  // one metre along +y
  EXPECT_NEAR(ekf.pose().x, 0.0, 1e-12);
  EXPECT_NEAR(ekf.pose().y, 1.0, 1e-12);
  EXPECT_NEAR(ekf.pose().theta, M_PI / 2, 1e-12);
  // The increment's x noise is now along world y.
  EXPECT_NEAR(ekf.pose_cov()(0, 0), 0.01, 1e-12);
  EXPECT_NEAR(ekf.pose_cov()(1, 1), 0.04, 1e-12);
  EXPECT_NEAR(ekf.pose_cov()(2, 2), 0.0025, 1e-12);
}

TEST(experiments_Ekf, ReobservingShrinksTheUncertaintyAndKeepsPd) {
  EkfSlam2D ekf({0.05, 0.01});
  ekf.update({{0, 3.0, 0.3}, {1, 5.0, -0.4}});
  const Eigen::Matrix3d Q = Eigen::Vector3d(0.01, 0.01, 1e-4).asDiagonal();
  ekf.predict(Pose2D(0.5, 0, 0), Q);
  const double before = ekf.covariance().trace();
  // The predicted measurements themselves: the mean must not move.
  std::vector<RangeBearing> z;
  for (int k = 0; k < 2; ++k) {
    const Eigen::Vector2d d = ekf.landmark(k) - Eigen::Vector2d(ekf.pose().x, ekf.pose().y);
    z.push_back({ekf.landmark_ids()[k], d.norm(),
                 wrap_angle(std::atan2(d.y(), d.x()) - ekf.pose().theta)});
  }
  const Eigen::VectorXd x_before = ekf.state();
  ekf.update(z);
  EXPECT_LT((ekf.state() - x_before).norm(), 1e-12);
  EXPECT_LT(ekf.covariance().trace(), before);
  EXPECT_EQ(Eigen::LLT<Eigen::MatrixXd>(ekf.covariance()).info(), Eigen::Success);
}

// Normalised estimation error squared of the final map, averaged over runs:
// a consistent filter gives about 2 per landmark; an inconsistent one (wrong
// Jacobian, noise applied in the wrong frame) gives far more.
TEST(experiments_Ekf, ConsistentOnTheSimulatedPath) {
  LandmarkSimOptions o;
  o.path_length = 20.0;
  o.landmarks = 30;
  o.x_max = 20.0;
  double nees = 0.0;
  int count = 0;
  for (int run = 0; run < 20; ++run) {
    Random rng(100 + run);
    const LandmarkSim sim = simulate_straight_path(o, rng);
    const EkfSlam2D ekf = run_ekf(sim, o);
    // Errors relative to the first pose's frame, which is the map frame of
    // both the truth and the filter (the robot starts exactly at the origin).
    for (int k = 0; k < ekf.landmark_count(); ++k) {
      const Point2D t = sim.landmarks[ekf.landmark_ids()[k]];
      const Eigen::Vector2d e = ekf.landmark(k) - Eigen::Vector2d(t.x, t.y);
      nees += e.dot(ekf.landmark_cov(k).ldlt().solve(e));
      ++count;
    }
  }
  ASSERT_GT(count, 100);
  const double mean = nees / count;
  EXPECT_GT(mean, 1.0);
  EXPECT_LT(mean, 4.0);
}

}  // namespace
}  // namespace hmt::experiments

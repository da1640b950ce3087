// The compact EKF against MRPT's CRangeBearingKFSLAM2D on the same odometry
// and observations: same models, so the same state and joint covariance.
#include <gtest/gtest.h>

#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/slam/CRangeBearingKFSLAM2D.h>

#include "hmt/experiments/ekf_slam.h"

namespace hmt::experiments {
namespace {

TEST(experiments_EkfVsMrpt, SameStateAndCovariance) {
  LandmarkSimOptions o;
  o.landmarks = 20;
  o.path_length = 8.0;
  o.x_min = 0.5;
  o.x_max = 10.0;
  o.half_width = 4.0;
  // A seed whose first observation sees landmarks: MRPT's filter skips the
  // prediction while its map is empty, this one does not.
  LandmarkSim sim;
  for (uint64_t seed = 1;; ++seed) {
    Random rng(seed);
    sim = simulate_straight_path(o, rng);
    if (sim.steps.front().z.size() >= 2) break;
  }
  // MRPT stores ranges and bearings as float: give both filters those.
  for (SimStep& s : sim.steps)
    for (RangeBearing& m : s.z) {
      m.range = static_cast<float>(m.range);
      m.bearing = static_cast<float>(m.bearing);
    }

  const EkfSlam2D mine = run_ekf(sim, o);

  mrpt::slam::CRangeBearingKFSLAM2D kf;
  kf.options.std_sensor_range = static_cast<float>(o.range_std);
  kf.options.std_sensor_yaw = static_cast<float>(o.bearing_std);
  kf.options.create_simplemap = false;
  kf.KF_options.verbosity_level = mrpt::system::LVL_ERROR;
  mrpt::math::CMatrixDouble33 Q;
  Q.setZero();
  Q(0, 0) = Q(1, 1) = o.odo_xy_std * o.odo_xy_std;
  Q(2, 2) = o.odo_phi_std * o.odo_phi_std;
  for (size_t t = 0; t < sim.steps.size(); ++t) {
    const SimStep& s = sim.steps[t];
    auto acts = mrpt::obs::CActionCollection::Create();
    mrpt::obs::CActionRobotMovement2D act;
    const mrpt::poses::CPose2D u(s.odometry.x, s.odometry.y, s.odometry.theta);
    mrpt::math::CMatrixDouble33 cov = Q;
    if (t == 0) cov.setZero();
    act.poseChange = mrpt::poses::CPosePDFGaussian::Create(u, cov);
    act.rawOdometryIncrementReading = u;
    acts->insert(act);
    auto sf = mrpt::obs::CSensoryFrame::Create();
    auto obs = mrpt::obs::CObservationBearingRange::Create();
    for (const RangeBearing& m : s.z) {
      mrpt::obs::CObservationBearingRange::TMeasurement meas;
      meas.range = static_cast<float>(m.range);
      meas.yaw = static_cast<float>(m.bearing);
      meas.pitch = 0.0f;
      meas.landmarkID = m.id;
      meas.covariance.setZero();
      obs->sensedData.push_back(meas);
    }
    sf->insert(obs);
    kf.processActionObservation(acts, sf);
  }
  mrpt::poses::CPosePDFGaussian robot;
  std::vector<mrpt::math::TPoint2D> lms;
  std::map<unsigned int, mrpt::maps::CLandmark::TLandmarkID> ids;
  mrpt::math::CVectorDouble state;
  mrpt::math::CMatrixDouble P;
  kf.getCurrentState(robot, lms, ids, state, P);

  ASSERT_EQ(static_cast<int>(lms.size()), mine.landmark_count());
  ASSERT_GT(mine.landmark_count(), 5);
  // Both append landmarks in the order first seen, so the states line up.
  for (int k = 0; k < mine.landmark_count(); ++k)
    ASSERT_EQ(ids.at(k), mine.landmark_ids()[k]);
  const Eigen::Index n = mine.state().size();
  ASSERT_EQ(static_cast<Eigen::Index>(state.size()), n);
  for (Eigen::Index i = 0; i < n; ++i)
    EXPECT_NEAR(state[i], mine.state()(i), 1e-6) << "state " << i;
  const double scale = mine.covariance().cwiseAbs().maxCoeff();
  double worst = 0.0;
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j)
      worst = std::max(worst, std::fabs(P(i, j) - mine.covariance()(i, j)));
  EXPECT_LT(worst, 1e-6 * scale);
}

}  // namespace
}  // namespace hmt::experiments

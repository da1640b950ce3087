// The MRPT adapter, in its own executable: it is the only test that needs
// the MRPT shared libraries (see CMakeLists.txt).
#include "hmt/area/mrpt_landmarks.h"

#include <gtest/gtest.h>
#include <mrpt/obs/CObservationBearingRange.h>

#include <cmath>

namespace hmt::area {
namespace {

TEST(area_MrptLandmarks, BearingRangeBecomesGaussiansInTheRobotFrame) {
  mrpt::obs::CObservationBearingRange obs;
  obs.sensorLocationOnRobot =
      mrpt::poses::CPose3D(0.5, 0.1, 0.0, M_PI / 2, 0, 0);
  obs.sensor_std_range = 0.1f;
  obs.sensor_std_yaw = 0.02f;
  mrpt::obs::CObservationBearingRange::TMeasurement m;
  m.range = 2.0f;
  m.yaw = 0.0f;
  m.pitch = 0.0f;
  m.landmarkID = -1;
  obs.sensedData.push_back(m);
  m.range = -1.0f;  // invalid, skipped
  obs.sensedData.push_back(m);
  const LandmarkObservation l = from_mrpt(obs);
  ASSERT_EQ(l.landmarks.size(), 1u);
  // Straight ahead of a sensor turned +90 deg: 2 m along the robot's +y.
  EXPECT_NEAR(l.landmarks[0].mean.x(), 0.5, 1e-6);
  EXPECT_NEAR(l.landmarks[0].mean.y(), 2.1, 1e-6);
  // Range noise along robot y, bearing noise (2 m * 0.02) along robot x.
  EXPECT_NEAR(l.landmarks[0].cov(1, 1), 0.01, 1e-7);
  EXPECT_NEAR(l.landmarks[0].cov(0, 0), 0.04 * 0.04, 1e-7);
  EXPECT_NEAR(l.landmarks[0].cov(0, 1), 0.0, 1e-9);

  // Per-measurement covariances when flagged valid.
  obs.sensedData.resize(1);
  obs.validCovariances = true;
  obs.sensedData[0].covariance.setZero();
  obs.sensedData[0].covariance(0, 0) = 0.09;
  obs.sensedData[0].covariance(1, 1) = 1e-4;
  const LandmarkObservation v = from_mrpt(obs);
  ASSERT_EQ(v.landmarks.size(), 1u);
  EXPECT_NEAR(v.landmarks[0].cov(1, 1), 0.09, 1e-7);
  EXPECT_NEAR(v.landmarks[0].cov(0, 0), 4.0 * 1e-4, 1e-7);

  // The same observation from two robot poses that see the same landmark.
  const Pose2D pa(0, 0, 0);
  EXPECT_DOUBLE_EQ(
      landmark_sso(l, PoseGaussian(pa), l, PoseGaussian(pa), SsoOptions{}),
      1.0);
}

}  // namespace
}  // namespace hmt::area

// What the rawlog readers and the writer take from (or put into) MRPT's
// objects, as plain data. The native reader fills these from the bytes, the
// MRPT plugin from MRPT's own objects, and both hand them to the same
// RawlogCollector: one conversion, whichever decoder ran.
#pragma once

#include <cstdint>
#include <vector>

namespace hmt::io::detail {

// mrpt::poses::CPose2D: phi as stored (not wrapped).
struct Pose2DRecord {
  double x = 0.0, y = 0.0, phi = 0.0;
};

// mrpt::poses::CPose3D: translation and rotation matrix (row-major).
struct Pose3DRecord {
  double x = 0.0, y = 0.0, z = 0.0;
  double rot[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
};

// mrpt::obs::CObservation2DRangeScan, the fields the conversion uses.
struct ScanRecord {
  float aperture = 0.0f;
  bool right_to_left = true;
  float max_range = 0.0f;
  Pose3DRecord sensor_pose;
  std::vector<float> ranges;
  std::vector<uint8_t> valid;  // non-zero = valid, one per range
  int64_t timestamp = 0;       // mrpt::Clock ticks; 0 = no time
};

// mrpt::obs::CActionRobotMovement2D: the estimation method, the raw odometry
// increment, and the mean of the pose-change PDF when there is one.
struct MoveRecord {
  static constexpr int32_t kOdometry = 0;  // CActionRobotMovement2D::emOdometry
  int32_t method = kOdometry;
  Pose2DRecord raw_increment;
  bool has_pdf = false;
  Pose2DRecord pdf_mean;
};

}  // namespace hmt::io::detail

// TUM trajectory files: one pose per line, "timestamp x y z qx qy qz qw"
// (seconds, metres, unit quaternion), the format of the TUM RGB-D benchmark
// tools and of evo. Planar poses are written with z = 0 and the quaternion of
// a rotation about z by the heading.
#pragma once

#include <string>
#include <vector>

#include "hmt/common/pose2d.h"

namespace hmt::io {

struct StampedPose {
  double timestamp = 0.0;  // seconds
  hmt::Pose2D pose;
};

// Writes atomically: timestamps and metres with 6 decimals, the quaternion
// with 9. Throws hmt::OutputError if the file cannot be written or a pose is
// not finite.
void write_tum(const std::string& path, const std::vector<StampedPose>& traj);

// Reads a TUM file (gzip or plain); blank lines and lines starting with '#'
// are skipped. The heading is the yaw of the (normalised) quaternion; z is
// dropped. Throws hmt::InputError naming the line number for a line without
// exactly 8 numeric, finite fields or with a zero quaternion.
std::vector<StampedPose> read_tum(const std::string& path);

}  // namespace hmt::io

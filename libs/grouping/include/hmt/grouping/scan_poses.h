// Where each scan of a log was taken: from the log's own odometry, or from a
// trajectory file (e.g. the output of a SLAM run) matched by timestamp.
// The poses are robot poses in one common frame; each scan's sensor_pose
// places the sensor on the robot.
#pragma once

#include <string>
#include <vector>

#include "hmt/common/pose2d.h"
#include "hmt/common/sensor_data.h"
#include "hmt/io/tum.h"

namespace hmt::grouping {

struct ScanPoses {
  std::vector<Pose2D> pose;     // one per scan considered
  std::vector<char> has_pose;   // 0: no pose within the tolerance (skipped)
  size_t missing = 0;           // scans with has_pose == 0
  std::string source;           // "odometry" or the trajectory file's path

  size_t size() const { return pose.size(); }
};

// The first `n` scans (all if n == 0 or n > the log) at the accumulated
// odometry, the first scan at the origin.
ScanPoses odometry_poses(const Log& log, size_t n = 0);

// Reads a trajectory file, gzip or plain, in either of two text formats told
// apart by the field count of the first data line ('#' comments and blank
// lines skipped): 8 fields = TUM ("timestamp x y z qx qy qz qw", see
// hmt/io/tum.h); 4 fields = "timestamp x y theta" (the datasets' reference
// files). Throws hmt::InputError naming the file and line for a missing or
// empty file, another field count, a line with a different count than the
// first, or a non-numeric / non-finite field.
std::vector<io::StampedPose> read_pose_file(const std::string& path);

// The first `n` scans (0 = all), each at the pose of `traj` with the nearest
// timestamp if it is within `tolerance` seconds, else without a pose. Ties
// go to the earlier pose. Throws hmt::InputError (naming `traj_name`) when no
// scan gets a pose: the file does not belong to the log.
ScanPoses match_poses(const Log& log, const std::vector<io::StampedPose>& traj,
                      double tolerance, const std::string& traj_name,
                      size_t n = 0);

}  // namespace hmt::grouping

// The internal stream -> a ROS 1 bag, as a 2D laser robot records one: for
// the tests of the bag reader and the log-to-bag tool (a CARMEN log turned
// into a bag maps like the log itself).
//
//  - one sensor_msgs/LaserScan per step on `scan_topic`, frame
//    `laser_frame`, header.stamp the step's timestamp (to the nanosecond);
//  - odometry at each scan's stamp: the given poses (e.g. a CARMEN log's own,
//    read_carmen()), else the increments accumulated from the origin; the
//    yaw is encoded so that the bag reader decodes it to exactly the same
//    double. As nav_msgs/Odometry on `odom_topic` (frame_id odom_frame,
//    child_frame_id base_frame), or as /tf transforms odom_frame ->
//    base_frame (`odometry = kTf`);
//  - the laser's mounting once on /tf_static, base_frame -> laser_frame;
//  - beams as ROS has them: range_min 0 and range_max the largest float
//    below max_range, so exactly the valid readings are <= range_max; an
//    invalid reading that would look valid (e.g. CARMEN's constant beams) is
//    written as NaN, every other reading as it is.
// Record times are the stamps, kept increasing (1 us apart at least) where
// the log's clock goes back, so the bag's order is the log's order.
#pragma once

#include <string>
#include <vector>

#include "hmt/common/sensor_data.h"

namespace hmt::io {

struct BagWriteOptions {
  enum class Odometry { kTopic, kTf } odometry = Odometry::kTopic;
  std::string scan_topic = "/scan";
  std::string odom_topic = "/odom";
  std::string odom_frame = "odom";
  std::string base_frame = "base_link";
  std::string laser_frame = "laser";
};

// Writes atomically (temporary file + rename). Throws hmt::OutputError if
// the file cannot be written or the log cannot be represented (no steps,
// scans with different mountings, a timestamp before 1970).
void write_bag(const hmt::Log& log, const std::string& path,
               const BagWriteOptions& options = {},
               const std::vector<Pose2D>* odometry = nullptr);

}  // namespace hmt::io

// ROS 1 bags (.bag, format 2.0) -> the internal stream.
//
// A bag holds timestamped messages on topics; a 2D laser robot's bag holds
// sensor_msgs/LaserScan, odometry as nav_msgs/Odometry and/or as transforms
// on /tf (tf2_msgs/TFMessage), and the sensors' mountings on /tf_static. The
// bag is read with Debian's rosbag storage library and ROS message headers,
// through a plugin loaded only when a bag is read (src/rosbag_plugin_abi.h), so
// that reading other logs never maps ROS's libraries (and libpython, which
// they pull in) into the process.
//
// One step per LaserScan message of the scan topic, in the bag's order
// (recording time), stamped with the scan's header.stamp:
//  - odometry: the pose of the robot frame in the odometry frame at the
//    scan's stamp, interpolated (linearly in position, slerp in rotation)
//    between the odometry samples around it (a sample at the very stamp is
//    taken as it is); step k's increment is pose(k-1)^-1 (+) pose(k), as the
//    CARMEN reader does. Odometry comes from the nav_msgs/Odometry topic
//    (robot frame: its child_frame_id, else base_frame), or else from /tf:
//    the chain of transforms odom_frame -> ... -> base_frame, every link
//    interpolated at the stamp (static ones from /tf_static as they are;
//    tf2_msgs/TFMessage, or tf/tfMessage as older bags have it).
//  - the laser's mounting: the transform robot frame -> the scan's
//    header.frame_id in /tf and /tf_static at the stamp, composed along the
//    chain, or `laser_pose` when given. A laser mounted upside down (its z
//    axis pointing down) has its bearings mirrored, as the rawlog reader
//    does; a laser tilted more than kBagMaxLaserTilt off level is an error.
//  - a scan whose odometry or mounting cannot be had at its stamp (before
//    the first or after the last sample of a link) is left out, as a ROS
//    node waiting for its transforms would; a bag where that leaves no scan
//    is an error saying why.
//  - beams: bearings increase (a scan with angle_increment < 0 is reversed);
//    a reading is valid iff it is finite, > 0 (and not subnormal) and within [range_min,
//    range_max] (ROS's convention, REP 117). max_range is the smallest float
//    above range_max, so "valid iff < max_range" means the same as ROS's
//    "<= range_max". +inf readings are stored as max_range, NaN and -inf as
//    0 (both invalid).
// Messages are checked against the definitions this reader decodes: the
// type name and the md5sum of the connection's definition.
// The bag is read in two passes, so that it takes the memory of one scan
// besides its odometry and transforms (held whole) and ~180 bytes per scan
// message: the first decodes every message of the topics above but keeps
// of a scan only its header and fields, not its readings, and makes every
// decision above; the second decodes the scan topic's messages again, one
// at a time, as the steps are taken (open_log(), log_stream.h).
#pragma once

#include <string>

#include "hmt/common/config.h"
#include "hmt/common/pose2d.h"
#include "hmt/common/sensor_data.h"

namespace hmt::io {

constexpr double kBagMaxLaserTilt = 10.0 * M_PI / 180.0;  // rad off level

struct BagOptions {
  // The sensor_msgs/LaserScan topic; "auto": the bag's only one.
  std::string scan_topic = "auto";
  // The nav_msgs/Odometry topic; "auto": the bag's only one, or /tf if it
  // has none; "tf": /tf even when the bag has an Odometry topic.
  std::string odom_topic = "auto";
  // Frames of the odometry chain in /tf (and the robot frame of an
  // Odometry topic whose messages name no child frame).
  std::string odom_frame = "odom";
  std::string base_frame = "base_link";
  // The laser in the robot frame; unset: from /tf and /tf_static.
  bool has_laser_pose = false;
  Pose2D laser_pose;

  // Reads [section] scan_topic, odom_topic, odom_frame, base_frame and
  // laser_pose ("auto" or "x y yaw", metres and radians); throws
  // hmt::ConfigError for an invalid value.
  void load(Config& cfg, const std::string& section);
};

// The step's conventions are above. Throws hmt::InputError with a one-line
// message naming the file and the problem: not a bag, truncated or
// unindexed, no (or several, none named) LaserScan topics, a named topic
// missing or of another type, a message definition other than the one
// decoded, an undecodable message, no odometry at all, no laser mounting,
// no scan with odometry and mounting at its stamp. All of these are found
// by the first pass, before any step; a bag that changes between the two
// passes is an error naming it. It is the stream open_log() returns for a
// bag, drained.
hmt::Log read_bag(const std::string& path, const BagOptions& options = {});

}  // namespace hmt::io

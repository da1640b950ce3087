// What a ROS bag holds that the bag reader uses, as plain structs. The ROS
// plugin (libs/io/plugin/rosbag_reader.cc) decodes the messages into these
// in two passes: first BagContents (the topics, the odometry and transforms
// whole, the scans without their readings), then the chosen topic's scans
// one BagScan at a time. bag_log.cc, free of ROS, makes every decision from
// the first pass and turns each scan of the second into a step. Keeping the
// decoding apart lets the choice of topics, the transform chains and the
// interpolation be tested without writing bags.
#pragma once

#include <Eigen/Geometry>
#include <map>
#include <string>
#include <vector>

namespace hmt::io::detail {

// The message types read, by their ROS names.
constexpr const char* kLaserScanType = "sensor_msgs/LaserScan";
constexpr const char* kOdometryType = "nav_msgs/Odometry";
constexpr const char* kTfMessageType = "tf2_msgs/TFMessage";
// tf (ROS 1's first transform library) recorded the same message, by the
// same definition, under its own name; older bags have it on /tf.
constexpr const char* kTfV1MessageType = "tf/tfMessage";
constexpr const char* kTfTopic = "/tf";
constexpr const char* kTfStaticTopic = "/tf_static";

struct BagTopic {
  std::string name;
  std::string datatype;
  std::string md5sum;
  // False when the type is one of the above but its definition (md5sum)
  // differs from the one decoded: the messages were not read.
  bool definition_matches = true;
  std::string expected_md5sum;  // of the decoded definition, when it does not match
  size_t messages = 0;
};

// A LaserScan message but its readings: what the choices need, and all
// the first pass keeps of a scan.
struct BagScanInfo {
  double stamp = 0.0;  // header.stamp, seconds
  std::string frame_id;
  float angle_min = 0.0f, angle_max = 0.0f, angle_increment = 0.0f;
  float range_min = 0.0f, range_max = 0.0f;
  size_t beams = 0;  // how many readings (ranges) it has
};

// A LaserScan message whole, as the second pass decodes it.
struct BagScan {
  BagScanInfo info;
  std::vector<float> ranges;  // info.beams of them
};

// A stamped rigid transform: the pose of `child` in `parent`.
struct BagTransform {
  double stamp = 0.0;
  std::string parent, child;
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
};

// What the first pass reads.
struct BagContents {
  std::vector<BagTopic> topics;  // every topic of the bag, sorted by name
  // The decoded messages, per topic, in the bag's order.
  std::map<std::string, std::vector<BagScanInfo>> scans;
  std::map<std::string, std::vector<BagTransform>> odometry;  // nav_msgs/Odometry
  std::vector<BagTransform> tf;         // every transform of /tf
  std::vector<BagTransform> tf_static;  // every transform of /tf_static
};

}  // namespace hmt::io::detail

// The ROS bag plugin: opens a bag with Debian's rosbag storage library and
// decodes the LaserScan, Odometry and TFMessage messages with the ROS
// message headers (sensor_msgs, nav_msgs, tf2_msgs) into plain structs
// (src/bag_contents.h). Everything else (which topic, transform chains,
// interpolation) is done by hmt_io, free of ROS.
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <exception>
#include <set>
#include <string>

#include "bag_contents.h"
#include "hmt/common/error.h"
#include "rosbag_plugin_abi.h"

namespace hmt::io::detail {
namespace {

// Whether messages of this type are decoded, and if so whether the
// connection's definition is the one the headers decode.
bool is_tf_type(const std::string& datatype) {
  return datatype == kTfMessageType || datatype == kTfV1MessageType;
}
bool decoded_type(const std::string& datatype) {
  return datatype == kLaserScanType || datatype == kOdometryType || is_tf_type(datatype);
}
std::string decoded_md5sum(const std::string& datatype) {
  if (datatype == kLaserScanType) return ros::message_traits::MD5Sum<sensor_msgs::LaserScan>::value();
  if (datatype == kOdometryType) return ros::message_traits::MD5Sum<nav_msgs::Odometry>::value();
  if (is_tf_type(datatype)) return ros::message_traits::MD5Sum<tf2_msgs::TFMessage>::value();
  return "";
}

BagTransform to_transform(const std_msgs::Header& header, const std::string& child,
                          const geometry_msgs::Point& p, const geometry_msgs::Quaternion& q) {
  BagTransform t;
  t.stamp = header.stamp.toSec();
  t.parent = header.frame_id;
  t.child = child;
  t.translation = Eigen::Vector3d(p.x, p.y, p.z);
  t.rotation = Eigen::Quaterniond(q.w, q.x, q.y, q.z);
  return t;
}

BagTransform to_transform(const geometry_msgs::TransformStamped& ts) {
  geometry_msgs::Point p;
  p.x = ts.transform.translation.x;
  p.y = ts.transform.translation.y;
  p.z = ts.transform.translation.z;
  return to_transform(ts.header, ts.child_frame_id, p, ts.transform.rotation);
}

BagScan to_scan(const sensor_msgs::LaserScan& m) {
  BagScan s;
  s.stamp = m.header.stamp.toSec();
  s.frame_id = m.header.frame_id;
  s.angle_min = m.angle_min;
  s.angle_max = m.angle_max;
  s.angle_increment = m.angle_increment;
  s.range_min = m.range_min;
  s.range_max = m.range_max;
  s.ranges = m.ranges;
  return s;
}

template <class Msg>
boost::shared_ptr<Msg> decode(const rosbag::MessageInstance& m, size_t index) {
  try {
    auto msg = m.instantiate<Msg>();
    if (!msg) throw std::runtime_error("its definition does not match");
    return msg;
  } catch (const std::exception& e) {
    throw InputError("message " + std::to_string(index) + " on topic '" +
                     m.getTopic() + "' (" + m.getDataType() +
                     ") cannot be decoded: " + e.what());
  }
}

BagContents read_contents(const std::string& path) {
  rosbag::Bag bag;
  try {
    bag.open(path, rosbag::bagmode::Read);
  } catch (const rosbag::BagUnindexedException& e) {
    throw InputError("ROS bag '" + path +
                     "' has no index: it was not closed (recording interrupted) "
                     "or is truncated; 'rosbag reindex' repairs it");
  } catch (const rosbag::BagIOException& e) {
    // Opening reads the header, then the index at the end of the file.
    throw InputError("ROS bag '" + path + "' is truncated or damaged (rosbag: " + e.what() + ")");
  } catch (const std::exception& e) {
    throw InputError("ROS bag '" + path + "' cannot be opened: " + e.what());
  }
  BagContents out;
  std::set<std::string> wanted;
  {
    rosbag::View all(bag);
    std::map<std::string, BagTopic> topics;
    for (const rosbag::ConnectionInfo* c : all.getConnections()) {
      auto [it, fresh] = topics.try_emplace(c->topic);
      BagTopic& t = it->second;
      if (fresh) {
        t.name = c->topic;
        t.datatype = c->datatype;
        t.md5sum = c->md5sum;
      } else if (t.datatype != c->datatype) {
        // Two publishers of different types on one topic: never ours.
        t.datatype += "|" + c->datatype;
      }
      if (decoded_type(c->datatype) && c->md5sum != decoded_md5sum(c->datatype)) {
        t.definition_matches = false;
        t.md5sum = c->md5sum;
        t.expected_md5sum = decoded_md5sum(c->datatype);
      }
    }
    for (auto& [name, t] : topics) {
      t.messages = rosbag::View(bag, rosbag::TopicQuery(name)).size();
      const bool tf = is_tf_type(t.datatype) && (name == kTfTopic || name == kTfStaticTopic);
      if (t.definition_matches &&
          (t.datatype == kLaserScanType || t.datatype == kOdometryType || tf))
        wanted.insert(name);
      out.topics.push_back(t);
    }
  }
  if (wanted.empty()) return out;
  const std::vector<std::string> wanted_list(wanted.begin(), wanted.end());
  rosbag::View view(bag, rosbag::TopicQuery(wanted_list));
  std::map<std::string, size_t> counts;
  for (const rosbag::MessageInstance& m : view) {
    const std::string& topic = m.getTopic();
    const size_t index = counts[topic]++;
    const std::string& type = m.getDataType();
    if (type == kLaserScanType) {
      out.scans[topic].push_back(to_scan(*decode<sensor_msgs::LaserScan>(m, index)));
    } else if (type == kOdometryType) {
      const auto o = decode<nav_msgs::Odometry>(m, index);
      out.odometry[topic].push_back(
          to_transform(o->header, o->child_frame_id, o->pose.pose.position,
                       o->pose.pose.orientation));
    } else if (is_tf_type(type)) {
      const auto tf = decode<tf2_msgs::TFMessage>(m, index);
      auto& dst = topic == kTfStaticTopic ? out.tf_static : out.tf;
      for (const auto& ts : tf->transforms) dst.push_back(to_transform(ts));
    }
  }
  return out;
}

}  // namespace
}  // namespace hmt::io::detail

extern "C" __attribute__((visibility("default")))
hmt::io::detail::BagReadStatus hmt_io_rosbag_read_contents_v1(
    const char* path, hmt::io::detail::BagContents* contents, std::string* error) {
  using hmt::io::detail::BagReadStatus;
  try {
    *contents = hmt::io::detail::read_contents(path);
    return BagReadStatus::kOk;
  } catch (const hmt::InputError& e) {
    *error = e.what();
    return BagReadStatus::kInputError;
  } catch (const rosbag::BagException& e) {
    // Damage found while reading the chunks (the index was readable).
    *error = std::string("ROS bag '") + path + "' is damaged: " + e.what();
    return BagReadStatus::kInputError;
  } catch (const std::exception& e) {
    *error = e.what();
    return BagReadStatus::kFailure;
  }
}

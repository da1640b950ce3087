// The ROS bag plugin: opens a bag with Debian's rosbag storage library and
// decodes the LaserScan, Odometry and TFMessage messages with the ROS
// message headers (sensor_msgs, nav_msgs, tf2_msgs) into plain structs
// (src/bag_contents.h), in the two passes of src/rosbag_plugin_abi.h.
// Everything else (which topic, transform chains, interpolation) is done by
// hmt_io, free of ROS.
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <exception>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

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

BagScanInfo to_scan_info(const sensor_msgs::LaserScan& m) {
  BagScanInfo s;
  s.stamp = m.header.stamp.toSec();
  s.frame_id = m.header.frame_id;
  s.angle_min = m.angle_min;
  s.angle_max = m.angle_max;
  s.angle_increment = m.angle_increment;
  s.range_min = m.range_min;
  s.range_max = m.range_max;
  s.beams = m.ranges.size();
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

void open_bag(rosbag::Bag& bag, const std::string& path) {
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
}

// Every topic of the bag, and into `decoded` the names of those whose
// messages are decoded: LaserScan and Odometry topics, /tf and /tf_static,
// of the definitions the headers decode.
std::vector<BagTopic> read_topics(rosbag::Bag& bag, std::vector<std::string>& decoded) {
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
  std::vector<BagTopic> out;
  decoded.clear();
  for (auto& [name, t] : topics) {
    t.messages = rosbag::View(bag, rosbag::TopicQuery(name)).size();
    const bool tf = is_tf_type(t.datatype) && (name == kTfTopic || name == kTfStaticTopic);
    if (t.definition_matches &&
        (t.datatype == kLaserScanType || t.datatype == kOdometryType || tf))
      decoded.push_back(name);
    out.push_back(t);
  }
  return out;
}

// The first pass. Every message of the decoded topics is decoded, scans
// included (so that one that cannot be is found here, before the first
// step), but a scan's readings are dropped as soon as they are counted.
BagContents read_contents(const std::string& path) {
  rosbag::Bag bag;
  open_bag(bag, path);
  BagContents out;
  std::vector<std::string> decoded;
  out.topics = read_topics(bag, decoded);
  if (decoded.empty()) return out;
  rosbag::View view(bag, rosbag::TopicQuery(decoded));
  std::map<std::string, size_t> counts;
  for (const rosbag::MessageInstance& m : view) {
    const std::string& topic = m.getTopic();
    const size_t index = counts[topic]++;
    const std::string& type = m.getDataType();
    if (type == kLaserScanType) {
      out.scans[topic].push_back(to_scan_info(*decode<sensor_msgs::LaserScan>(m, index)));
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

// Runs `read`, saying how it ended as the plugin's functions do; damage
// rosbag finds while reading the chunks (the index was readable) is a bad
// file.
template <class Read>
PluginStatus guarded(const std::string& path, std::string* error, Read&& read) {
  return plugin_status_of(error, [&] {
    try {
      read();
    } catch (const rosbag::BagException& e) {
      throw InputError("ROS bag '" + path + "' is damaged: " + e.what());
    }
  });
}

PluginStatus read_contents_of(const char* path, BagContents* contents, std::string* error) {
  return guarded(path, error, [&] { *contents = read_contents(path); });
}

}  // namespace

// The second pass. rosbag's View iterates lazily: a message is read from
// the file when it is instantiated, so one scan is held at a time. The view
// is the first pass's, over all the decoded topics, so that the scans come
// in its order: a view orders messages of one record time on different
// connections by what else it holds.
struct BagScanCursor {
  BagScanCursor(const std::string& bag_path, const std::string& scan_topic)
      : path(bag_path), topic(scan_topic) {
    open_bag(bag, path);
    std::vector<std::string> decoded;
    read_topics(bag, decoded);
    view = std::make_unique<rosbag::View>(bag, rosbag::TopicQuery(decoded));
    at = view->begin();
  }

  bool next(BagScan& out) {
    for (; at != view->end(); ++at) {
      if (at->getTopic() != topic) continue;
      const auto m = decode<sensor_msgs::LaserScan>(*at, index++);
      out.info = to_scan_info(*m);
      out.ranges = std::move(m->ranges);
      ++at;
      return true;
    }
    return false;
  }

  std::string path, topic;
  rosbag::Bag bag;
  std::unique_ptr<rosbag::View> view;  // refers to `bag`
  rosbag::View::iterator at;           // refers to `view`
  size_t index = 0;                    // of the next message on the topic
};

namespace {

PluginStatus open_scans(const char* path, const char* topic, BagScanCursor** cursor,
                        std::string* error) {
  return guarded(path, error, [&] { *cursor = new BagScanCursor(path, topic); });
}

PluginStatus next_scan(BagScanCursor* cursor, BagScan* scan, bool* got, std::string* error) {
  return guarded(cursor->path, error, [&] { *got = cursor->next(*scan); });
}

void close_scans(BagScanCursor* cursor) { delete cursor; }

}  // namespace
}  // namespace hmt::io::detail

extern "C" __attribute__((visibility("default")))
const hmt::io::detail::RosbagPlugin* hmt_io_rosbag_plugin_v2() {
  using namespace hmt::io::detail;
  static const RosbagPlugin plugin{&read_contents_of, &open_scans, &next_scan, &close_scans};
  return &plugin;
}

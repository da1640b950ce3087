#include "hmt/io/bag_writer.h"

#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <system_error>
#include <unistd.h>

#include "bag_frames.h"
#include "hmt/common/error.h"

namespace hmt::io {
namespace {

// The rotation by `yaw` about z. (sin, cos) of yaw/2 decodes to yaw only to
// an ulp or so; among the quaternions a few ulps around it, the first
// (closest) one the bag reader decodes to exactly `yaw` is taken, so that
// a log's odometry crosses the bag bit for bit (one within 2 ulps was found
// for each of 200000 random yaws).
geometry_msgs::Quaternion yaw_quaternion(double yaw) {
  const double z0 = std::sin(yaw / 2.0), w0 = std::cos(yaw / 2.0);
  auto step = [](double v, int k) {
    for (; k > 0; --k) v = std::nextafter(v, 2.0);
    for (; k < 0; ++k) v = std::nextafter(v, -2.0);
    return v;
  };
  geometry_msgs::Quaternion q;
  q.z = z0;
  q.w = w0;
  constexpr int kReach = 4;
  for (int d = 0; d <= 2 * kReach; ++d)
    for (int i = -kReach; i <= kReach; ++i) {
      const int j = d - std::abs(i);
      if (j < 0 || j > kReach) continue;
      for (const int sj : {j, -j}) {
        detail::BagTransform t;
        t.rotation = Eigen::Quaterniond(step(w0, sj), 0.0, 0.0, step(z0, i));
        if (detail::planar(detail::to_rigid(t, "yaw")).theta == yaw) {
          q.z = t.rotation.z();
          q.w = t.rotation.w();
          return q;
        }
        if (j == 0) break;
      }
    }
  return q;
}

geometry_msgs::TransformStamped transform(const ros::Time& stamp, const std::string& parent,
                                          const std::string& child, const Pose2D& p) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = stamp;
  t.header.frame_id = parent;
  t.child_frame_id = child;
  t.transform.translation.x = p.x;
  t.transform.translation.y = p.y;
  t.transform.rotation = yaw_quaternion(p.theta);
  return t;
}

sensor_msgs::LaserScan to_message(const LaserScan& s, const ros::Time& stamp,
                                  const std::string& frame) {
  sensor_msgs::LaserScan m;
  m.header.stamp = stamp;
  m.header.frame_id = frame;
  const size_t n = s.size();
  m.angle_min = s.angle_min;
  m.angle_increment = s.angle_increment;
  m.angle_max = static_cast<float>(double(s.angle_min) + double(s.angle_increment) * double(n - 1));
  m.range_min = 0.0f;
  m.range_max = std::nextafter(s.max_range, 0.0f);
  m.ranges.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const float r = s.ranges[i];
    const bool looks_valid = r > 0.0f && r <= m.range_max;
    const bool valid = i < s.valid.size() && s.valid[i];
    m.ranges[i] = (valid || !looks_valid) ? r : std::numeric_limits<float>::quiet_NaN();
  }
  return m;
}

void write(const Log& log, const std::string& path, const BagWriteOptions& o,
           const std::vector<Pose2D>* odometry) {
  rosbag::Bag bag;
  bag.open(path, rosbag::bagmode::Write);
  const Pose2D mount = log.steps.front().scan.sensor_pose;
  Pose2D odom;
  ros::Time last_record;
  for (size_t k = 0; k < log.steps.size(); ++k) {
    const LogStep& step = log.steps[k];
    const Pose2D& m = step.scan.sensor_pose;
    if (m.x != mount.x || m.y != mount.y || m.theta != mount.theta)
      throw OutputError("cannot write '" + path + "': step " + std::to_string(k) +
                        " has another laser mounting than step 0 (a bag has one on /tf_static)");
    if (!(step.timestamp >= 0.0) || step.scan.size() == 0)
      throw OutputError("cannot write '" + path + "': step " + std::to_string(k) +
                        " has no beams or a timestamp before 1970");
    if (odometry)
      odom = (*odometry)[k];
    else if (step.has_odometry)
      odom = odom + step.odometry_increment;
    const ros::Time stamp(step.timestamp);
    ros::Time record = stamp;
    if (k > 0 && record < last_record + ros::Duration(1e-6)) record = last_record + ros::Duration(1e-6);
    last_record = record;
    if (k == 0) {
      tf2_msgs::TFMessage fixed;
      fixed.transforms.push_back(transform(stamp, o.base_frame, o.laser_frame, mount));
      bag.write("/tf_static", record, fixed);
    }
    if (o.odometry == BagWriteOptions::Odometry::kTopic) {
      nav_msgs::Odometry msg;
      msg.header.stamp = stamp;
      msg.header.frame_id = o.odom_frame;
      msg.child_frame_id = o.base_frame;
      msg.pose.pose.position.x = odom.x;
      msg.pose.pose.position.y = odom.y;
      msg.pose.pose.orientation = yaw_quaternion(odom.theta);
      bag.write(o.odom_topic, record, msg);
    } else {
      tf2_msgs::TFMessage tf;
      tf.transforms.push_back(transform(stamp, o.odom_frame, o.base_frame, odom));
      bag.write("/tf", record, tf);
    }
    bag.write(o.scan_topic, record, to_message(step.scan, stamp, o.laser_frame));
  }
  bag.close();
}

}  // namespace

void write_bag(const hmt::Log& log, const std::string& path, const BagWriteOptions& options,
               const std::vector<Pose2D>* odometry) {
  if (log.steps.empty()) throw OutputError("cannot write '" + path + "': the log has no steps");
  if (odometry && odometry->size() != log.steps.size())
    throw OutputError("cannot write '" + path + "': " + std::to_string(odometry->size()) +
                      " odometry poses for " + std::to_string(log.steps.size()) + " steps");
  // rosbag writes to a path of its own, so the atomic rename is done here.
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  try {
    write(log, tmp, options, odometry);
  } catch (const OutputError&) {
    std::remove(tmp.c_str());
    throw;
  } catch (const std::exception& e) {
    std::remove(tmp.c_str());
    throw OutputError("cannot write ROS bag '" + path + "': " + e.what());
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw OutputError("cannot move output into place at '" + path + "': " + ec.message());
  }
}

}  // namespace hmt::io

#include "bag_log.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <optional>

#include "hmt/common/error.h"

namespace hmt::io::detail {
namespace {

std::string topic_name(const std::string& t) {
  return !t.empty() && t[0] != '/' ? "/" + t : t;
}

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : ", ") + s;
  return out.empty() ? "none" : out;
}

template <class T>
bool same_bits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

// The same message, bit for bit (a NaN field is the same NaN).
bool same_scan(const BagScanInfo& a, const BagScanInfo& b) {
  return same_bits(a.stamp, b.stamp) && a.frame_id == b.frame_id &&
         same_bits(a.angle_min, b.angle_min) && same_bits(a.angle_max, b.angle_max) &&
         same_bits(a.angle_increment, b.angle_increment) &&
         same_bits(a.range_min, b.range_min) && same_bits(a.range_max, b.range_max) &&
         a.beams == b.beams;
}

// The decisions of the first pass, over the contents it read: the scan
// topic, the odometry, and for each scan of that topic in the bag's order
// whether odometry and a mounting exist at its stamp and its beams can be
// used. The first problem found, in that order, is the error.
class BagPlanner {
 public:
  BagPlanner(const std::string& source, const BagContents& c, const BagOptions& o)
      : source_(source), c_(c), o_(o) {}

  std::vector<BagSteps::Scan> plan(std::string& scan_topic) {
    scan_topic = choose(kLaserScanType, o_.scan_topic, "scan_topic");
    const std::vector<BagScanInfo>& scans = messages(c_.scans, scan_topic);
    const FrameTree tree(c_.tf, c_.tf_static, source_);
    Odometry odom = odometry(tree);

    std::vector<BagSteps::Scan> out(scans.size());
    std::optional<Pose2D> previous;
    size_t kept = 0;
    std::string first_skip;
    for (size_t k = 0; k < scans.size(); ++k) {
      const BagScanInfo& s = scans[k];
      out[k].info = s;
      std::string why;
      const auto pose = odom.pose_at(s.stamp, why);
      std::optional<Rigid> mount;
      if (pose) mount = mounting(tree, odom.robot_frame, s, why);
      if (!pose || !mount) {
        if (first_skip.empty())
          first_skip = "scan " + std::to_string(k) + ": " + why;
        continue;
      }
      check_beams(s, k, scan_topic, *mount);
      BagSteps::Scan& step = out[k];
      step.kept = true;
      if (previous) {
        step.has_odometry = true;
        step.odometry_increment = *pose - *previous;
      }
      previous = pose;
      step.mount = *mount;
      ++kept;
    }
    if (kept == 0)
      fail("none of the " + std::to_string(scans.size()) + " scans on '" + scan_topic +
           "' has odometry and a laser mounting at its stamp (" + first_skip + ")");
    return out;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError("ROS bag '" + source_ + "': " + what);
  }

  const BagTopic* find_topic(const std::string& name) const {
    for (const BagTopic& t : c_.topics)
      if (t.name == name) return &t;
    return nullptr;
  }

  std::vector<std::string> topics_of(const std::string& type) const {
    std::vector<std::string> out;
    for (const BagTopic& t : c_.topics)
      if (t.datatype == type) out.push_back(t.name);
    return out;
  }

  // The topic of `type` the option names, or the only one with "auto".
  std::string choose(const std::string& type, const std::string& option,
                     const std::string& key) const {
    const std::vector<std::string> candidates = topics_of(type);
    std::string name;
    if (option == "auto") {
      if (candidates.empty()) {
        std::vector<std::string> all;
        for (const BagTopic& t : c_.topics) all.push_back(t.name + " (" + t.datatype + ")");
        fail("no " + type + " topic (its topics: " + join(all) + ")");
      }
      if (candidates.size() > 1)
        fail("several " + type + " topics (" + join(candidates) +
             "): name one with [input] " + key);
      name = candidates.front();
    } else {
      name = topic_name(option);
      const BagTopic* t = find_topic(name);
      if (!t)
        fail("no topic '" + name + "' ([input] " + key + "; its " + type +
             " topics: " + join(candidates) + ")");
      if (t->datatype != type)
        fail("topic '" + name + "' ([input] " + key + ") is " + t->datatype + ", not " + type);
    }
    const BagTopic& t = *find_topic(name);
    if (!t.definition_matches)
      fail("topic '" + name + "' is " + type + " of another definition (md5sum " + t.md5sum +
           ", this reader decodes " + t.expected_md5sum + ")");
    return name;
  }

  template <class T>
  const std::vector<T>& messages(const std::map<std::string, std::vector<T>>& by_topic,
                                 const std::string& topic) const {
    const auto it = by_topic.find(topic);
    if (it == by_topic.end() || it->second.empty()) fail("topic '" + topic + "' has no messages");
    return it->second;
  }

  // Odometry as a function of time, and the frame it moves.
  struct Odometry {
    std::string robot_frame;
    std::function<std::optional<Rigid>(double, std::string&)> lookup;
    std::optional<Pose2D> pose_at(double t, std::string& why) const {
      const auto p = lookup(t, why);
      if (!p) return std::nullopt;
      return planar(*p);
    }
  };

  Odometry odometry(const FrameTree& tree) {
    std::string topic;
    if (o_.odom_topic != "tf") {
      if (o_.odom_topic != "auto" || !topics_of(kOdometryType).empty())
        topic = choose(kOdometryType, o_.odom_topic, "odom_topic");
    }
    Odometry out;
    if (!topic.empty()) {
      const std::vector<BagTransform>& msgs = messages(c_.odometry, topic);
      const std::string child = frame_name(msgs.front().child);
      out.robot_frame = child.empty() ? frame_name(o_.base_frame) : child;
      for (size_t k = 0; k < msgs.size(); ++k)
        series_.add(msgs[k].stamp,
                    to_rigid(msgs[k], "ROS bag '" + source_ + "': message " +
                                             std::to_string(k) + " on '" + topic + "'"));
      series_.finish();
      out.lookup = [this, topic](double t, std::string& why) {
        auto p = series_.at(t);
        if (!p) {
          char span[128];
          std::snprintf(span, sizeof span, "%.6f s is outside the span [%.6f, %.6f] s of ", t,
                        series_.first_stamp(), series_.last_stamp());
          why = span + topic;
        }
        return p;
      };
      return out;
    }
    // From /tf: odom_frame -> ... -> base_frame.
    const std::string odom = frame_name(o_.odom_frame), base = frame_name(o_.base_frame);
    out.robot_frame = base;
    const std::vector<std::string> frames = tree.frames();
    const bool has = tree.connected(odom, base);
    if (!has)
      fail(std::string(o_.odom_topic == "tf" ? "no odometry in /tf ([input] odom_topic = tf)"
                                             : "no odometry: no " + std::string(kOdometryType) +
                                                   " topic") +
           ", and /tf and /tf_static do not connect '" + odom + "' to '" + base +
           "' ([input] odom_frame, base_frame; frames there: " + join(frames) + ")");
    out.lookup = [&tree, odom, base](double t, std::string& why) {
      return tree.lookup(odom, base, t, why);
    };
    return out;
  }

  // The laser's pose in the robot frame at the scan's stamp.
  std::optional<Rigid> mounting(const FrameTree& tree, const std::string& robot,
                                const BagScanInfo& s, std::string& why) const {
    if (o_.has_laser_pose) {
      return Rigid{Eigen::Quaterniond(Eigen::AngleAxisd(o_.laser_pose.theta,
                                                        Eigen::Vector3d::UnitZ())),
                   Eigen::Vector3d(o_.laser_pose.x, o_.laser_pose.y, 0.0)};
    }
    const std::string laser = frame_name(s.frame_id);
    if (laser.empty()) {
      why = "the scan names no frame (header.frame_id); give [input] laser_pose";
      return std::nullopt;
    }
    if (laser == robot) return Rigid{};
    auto p = tree.lookup(robot, laser, s.stamp, why);
    if (!p) why = "no laser mounting: " + why + " (give [input] laser_pose)";
    return p;
  }

  // What makes a kept scan's beams unusable: all in its message's fields,
  // so that it is found on the first pass.
  void check_beams(const BagScanInfo& s, size_t k, const std::string& topic,
                   const Rigid& mount) const {
    const std::string which = "scan " + std::to_string(k) + " on '" + topic + "'";
    const size_t n = s.beams;
    if (n == 0) fail(which + " has no beams");
    if (!std::isfinite(s.angle_min) || !std::isfinite(s.angle_increment) ||
        (n > 1 && s.angle_increment == 0.0f))
      fail(which + " has no usable beam angles (angle_min " + std::to_string(s.angle_min) +
           ", angle_increment " + std::to_string(s.angle_increment) + ")");
    if (!(s.range_max > 0.0f) || !std::isfinite(s.range_max) || !(s.range_min >= 0.0f) ||
        s.range_min > s.range_max)
      fail(which + " has range limits [" + std::to_string(s.range_min) + ", " +
           std::to_string(s.range_max) + "]");
    const double up = mount.up();  // the laser's z axis, seen in the robot frame
    if (std::abs(up) < std::cos(kBagMaxLaserTilt))
      fail(which + ": its frame '" + s.frame_id + "' is tilted " +
           std::to_string(std::acos(std::min(1.0, std::abs(up))) * 180.0 / M_PI) +
           " degrees off level; a planar scan needs a level laser");
  }

  const std::string& source_;
  const BagContents& c_;
  const BagOptions& o_;
  TransformSeries series_;
};

// The beams of a scan the first pass kept (check_beams() passed).
LaserScan beams(const BagScan& scan, const Rigid& mount) {
  const BagScanInfo& s = scan.info;
  const size_t n = scan.ranges.size();
  const double up = mount.up();
  LaserScan out;
  out.timestamp = s.stamp;
  out.sensor_pose = planar(mount);
  out.max_range = std::nextafter(s.range_max, std::numeric_limits<float>::infinity());
  // Bearings as seen from above (mirrored for a laser mounted upside
  // down), then the beams in the order that makes them increase.
  const bool mirrored = up < 0.0;
  const float inc = mirrored ? -s.angle_increment : s.angle_increment;
  const float first = mirrored ? -s.angle_min : s.angle_min;
  const bool reverse = inc < 0.0f;
  if (reverse) {
    out.angle_min = static_cast<float>(double(first) + double(inc) * double(n - 1));
    out.angle_increment = -inc;
  } else {
    out.angle_min = first;
    out.angle_increment = inc;
  }
  out.ranges.resize(n);
  out.valid.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const float r = scan.ranges[reverse ? n - 1 - i : i];
    // isnormal: finite, neither zero nor subnormal (not a distance).
    const bool ok = std::isnormal(r) && r > 0.0f && r >= s.range_min && r <= s.range_max;
    out.valid[i] = ok ? 1 : 0;
    out.ranges[i] = std::isfinite(r) ? r : (r > 0.0f ? out.max_range : 0.0f);
  }
  return out;
}

}  // namespace

BagSteps::BagSteps(const std::string& source, const BagContents& contents,
                   const BagOptions& options)
    : source_(source) {
  scans_ = BagPlanner(source, contents, options).plan(scan_topic_);
  steps_ = static_cast<size_t>(
      std::count_if(scans_.begin(), scans_.end(), [](const Scan& s) { return s.kept; }));
}

bool BagSteps::step(size_t k, const BagScan& scan, LogStep& out) const {
  if (k >= scans_.size())
    changed(std::to_string(scans_.size()) + " scans on '" + scan_topic_ + "' at first, more then");
  if (!same_scan(scan.info, scans_[k].info) || scan.ranges.size() != scan.info.beams)
    changed("scan " + std::to_string(k) + " on '" + scan_topic_ + "' is not the one first read");
  const Scan& s = scans_[k];
  if (!s.kept) return false;
  out = LogStep();
  out.timestamp = s.info.stamp;
  out.has_odometry = s.has_odometry;
  out.odometry_increment = s.odometry_increment;
  out.scan = beams(scan, s.mount);
  return true;
}

void BagSteps::changed(const std::string& how) const {
  throw InputError("ROS bag '" + source_ + "' changed while it was read (" + how + ")");
}

}  // namespace hmt::io::detail

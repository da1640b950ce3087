#include <cmath>
#include <string_view>
#include <vector>

#include "hmt/io/rosbag.h"
#include "text_file.h"

namespace hmt::io {
namespace {

bool is_name(const std::string& s) {
  return !s.empty() && s.find_first_of(" \t\r\n") == std::string::npos;
}

}  // namespace

void BagOptions::load(Config& cfg, const std::string& section) {
  scan_topic = cfg.get_string(section, "scan_topic", scan_topic);
  odom_topic = cfg.get_string(section, "odom_topic", odom_topic);
  odom_frame = cfg.get_string(section, "odom_frame", odom_frame);
  base_frame = cfg.get_string(section, "base_frame", base_frame);
  const std::string pose = cfg.get_string(section, "laser_pose", "auto");
  require(is_name(scan_topic), section, "scan_topic", "'auto' or a topic name without blanks");
  require(is_name(odom_topic), section, "odom_topic",
          "'auto', 'tf' or a topic name without blanks");
  require(is_name(odom_frame) && odom_frame != "/", section, "odom_frame",
          "a frame name without blanks");
  require(is_name(base_frame) && base_frame != "/", section, "base_frame",
          "a frame name without blanks");
  require(odom_frame != base_frame, section, "base_frame", "a frame other than odom_frame");
  has_laser_pose = pose != "auto";
  if (has_laser_pose) {
    std::vector<std::string_view> fields;
    detail::split_fields(pose, fields);
    double v[3] = {0, 0, 0};
    bool ok = fields.size() == 3;
    for (size_t i = 0; ok && i < 3; ++i)
      ok = detail::parse_double(fields[i], v[i]) && std::isfinite(v[i]);
    require(ok, section, "laser_pose", "'auto' or 'x y yaw' (metres, metres, radians)");
    laser_pose = Pose2D(v[0], v[1], v[2]);
  }
}

}  // namespace hmt::io

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hmt/common/error.h"
#include "hmt/io/carmen.h"
#include "text_file.h"

namespace hmt::io {
namespace {

using detail::parse_double;
using detail::parse_int;

constexpr double kDeg = M_PI / 180.0;
constexpr long kMaxBeams = 100000;  // far above any real 2D scanner

// One scan as read from a line, before the log-wide decisions.
struct RawScan {
  std::vector<float> ranges;
  float angle_min = 0.0f;
  float angle_increment = 0.0f;
  Pose2D odometry;
  std::optional<Pose2D> sensor_pose;  // ROBOTLASER1 carries its own
  double timestamp = 0.0;
};

// The README's rule: the count tells the resolution of the SICK scanners
// these logs come from; first beam at -90 degrees (the robot's right).
double flaser_resolution(size_t n) {
  if (n == 180 || n == 181) return 1.0 * kDeg;
  if (n == 360 || n == 361) return 0.5 * kDeg;
  return n > 1 ? M_PI / double(n - 1) : 0.0;
}

class CarmenParser {
 public:
  explicit CarmenParser(const std::string& path) : path_(path) {}

  [[noreturn]] void fail(const std::string& problem) const {
    throw InputError("CARMEN log '" + path_ + "' line " +
                     std::to_string(line_no_) + ": " + problem);
  }

  void parse(const std::string& text) {
    std::vector<std::string_view> f;
    size_t pos = 0;
    while (pos < text.size()) {
      size_t end = text.find('\n', pos);
      if (end == std::string::npos) end = text.size();
      ++line_no_;
      detail::split_fields(std::string_view(text).substr(pos, end - pos), f);
      pos = end + 1;
      if (f.empty() || f[0][0] == '#') continue;
      const std::string_view type = f[0];
      if (!plausible_message_name(type))
        fail("'" + printable(type) + "' is not a CARMEN message name");
      if (type == "FLASER") {
        flaser_.push_back(parse_flaser(f));
      } else if (type == "ROBOTLASER1") {
        robotlaser_.push_back(parse_robotlaser(f));
      } else if (type == "PARAM") {
        parse_param(f);
      }
      // ODOM, TRUEPOS, RAWLASER*, SYNC, ...: not needed.
    }
  }

  hmt::Log finish(std::vector<Pose2D>* odometry) {
    // Logs with both carry the same scans twice; FLASER is the classic one.
    std::vector<RawScan>& scans = flaser_.empty() ? robotlaser_ : flaser_;
    if (scans.empty())
      throw InputError("CARMEN log '" + path_ +
                       "' holds no laser scans (no FLASER or ROBOTLASER1 "
                       "line in " + std::to_string(line_no_) + " lines)");
    const NoReturn no_return = find_no_return(scans);
    const std::vector<uint8_t> dead_beams = find_constant_beams(scans);

    hmt::Log log;
    log.source = path_;
    log.steps.reserve(scans.size());
    if (odometry) odometry->clear();
    for (size_t k = 0; k < scans.size(); ++k) {
      RawScan& s = scans[k];
      if (odometry) odometry->push_back(s.odometry);
      LogStep step;
      step.timestamp = s.timestamp;
      if (k > 0) {
        step.has_odometry = true;
        step.odometry_increment = s.odometry - scans[k - 1].odometry;
      }
      LaserScan& scan = step.scan;
      scan.timestamp = s.timestamp;
      scan.angle_min = s.angle_min;
      scan.angle_increment = s.angle_increment;
      scan.max_range = no_return.max_range;
      scan.sensor_pose = s.sensor_pose.value_or(Pose2D(laser_offset_, 0, 0));
      scan.valid.resize(s.ranges.size());
      for (size_t i = 0; i < s.ranges.size(); ++i) {
        const float r = s.ranges[i];
        const bool dead = i < dead_beams.size() && dead_beams[i];
        // Zero, and subnormal values (below 1.2e-38 m: a zero with rounding
        // noise, not a distance a laser measures), are no readings.
        scan.valid[i] = (std::isnormal(r) && r < no_return.max_range && !dead) ? 1 : 0;
      }
      scan.ranges = std::move(s.ranges);
      log.steps.push_back(std::move(step));
    }
    return log;
  }

 private:
  struct NoReturn {
    float max_range;
  };

  static bool plausible_message_name(std::string_view s) {
    if (s.empty() || !(s[0] >= 'A' && s[0] <= 'Z')) return false;
    return std::all_of(s.begin(), s.end(), [](char c) {
      return (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
    });
  }

  static std::string printable(std::string_view s) {
    std::string out;
    for (char c : s.substr(0, 24))
      out += (c >= 32 && c < 127) ? c : '?';
    if (s.size() > 24) out += "...";
    return out;
  }

  double number(const std::vector<std::string_view>& f, size_t i,
                const char* what) const {
    double v;
    if (!parse_double(f[i], v))
      fail(std::string(what) + " (field " + std::to_string(i + 1) + ") is '" +
           printable(f[i]) + "', not a number");
    if (!std::isfinite(v))
      fail(std::string(what) + " (field " + std::to_string(i + 1) + ") is " +
           printable(f[i]));
    return v;
  }

  size_t beam_count(const std::vector<std::string_view>& f, size_t i) const {
    long n;
    if (!parse_int(f[i], n))
      fail("the beam count (field " + std::to_string(i + 1) + ") is '" +
           printable(f[i]) + "', not an integer");
    if (n <= 0) fail("scan with " + std::to_string(n) + " beams");
    if (n > kMaxBeams) fail("absurd beam count " + std::to_string(n));
    return static_cast<size_t>(n);
  }

  void read_ranges(const std::vector<std::string_view>& f, size_t first,
                   size_t n, std::vector<float>& out) const {
    out.resize(n);
    for (size_t i = 0; i < n; ++i) {
      double r;
      if (!parse_double(f[first + i], r))
        fail("range " + std::to_string(i) + " is '" +
             printable(f[first + i]) + "', not a number");
      if (!std::isfinite(r) || r < 0.0)
        fail("range " + std::to_string(i) + " is " + printable(f[first + i]));
      // Ranges are held as floats: a larger value would become infinite.
      if (r > std::numeric_limits<float>::max())
        fail("range " + std::to_string(i) + " is " + printable(f[first + i]) +
             ", beyond what a float holds");
      out[i] = static_cast<float>(r);
    }
  }

  // FLASER n r1..rn x y theta odom_x odom_y odom_theta ts host logger_ts
  RawScan parse_flaser(const std::vector<std::string_view>& f) const {
    if (f.size() < 2) fail("FLASER without a beam count");
    const size_t n = beam_count(f, 1);
    if (f.size() != n + 11)
      fail("FLASER with " + std::to_string(n) + " beams needs " +
           std::to_string(n + 11) + " fields, found " +
           std::to_string(f.size()));
    RawScan s;
    read_ranges(f, 2, n, s.ranges);
    const size_t o = 2 + n;
    // x y theta (fields o..o+2) are checked but the odometry is used.
    for (size_t i = o; i < o + 3; ++i) number(f, i, "a pose value");
    s.odometry = Pose2D(number(f, o + 3, "odom_x"), number(f, o + 4, "odom_y"),
                        wrap_angle(number(f, o + 5, "odom_theta")));
    s.timestamp = number(f, o + 6, "the timestamp");
    const double res = flaser_resolution(n);
    s.angle_min = static_cast<float>(-M_PI / 2.0);
    s.angle_increment = static_cast<float>(res);
    return s;
  }

  // ROBOTLASER1 type start_angle fov resolution max_range accuracy
  //   remission_mode n r1..rn m rem1..remm laser_x laser_y laser_theta
  //   robot_x robot_y robot_theta tv rv forward_safety side_safety turn_axis
  //   ts host logger_ts
  RawScan parse_robotlaser(const std::vector<std::string_view>& f) const {
    if (f.size() < 9) fail("ROBOTLASER1 too short for a beam count");
    const size_t n = beam_count(f, 8);
    if (f.size() < n + 10) fail("ROBOTLASER1 too short for its beams");
    long m;
    if (!parse_int(f[9 + n], m) || m < 0 || m > kMaxBeams)
      fail("the remission count is '" + printable(f[9 + n]) + "'");
    const size_t want = n + static_cast<size_t>(m) + 24;
    if (f.size() != want)
      fail("ROBOTLASER1 with " + std::to_string(n) + " beams and " +
           std::to_string(m) + " remissions needs " + std::to_string(want) +
           " fields, found " + std::to_string(f.size()));
    RawScan s;
    const double start = number(f, 2, "start_angle");
    const double resolution = number(f, 4, "angular_resolution");
    // Radians: the beams of a 2D scanner span at most one turn.
    if (std::abs(start) > 2.0 * M_PI)
      fail("start_angle " + printable(f[2]) + " is not an angle in [-2 pi, 2 pi]");
    if (std::abs(resolution) * double(n - 1) > 2.0 * M_PI)
      fail("angular_resolution " + printable(f[4]) + " makes " + std::to_string(n) +
           " beams span more than a full turn");
    s.angle_min = static_cast<float>(start);
    s.angle_increment = static_cast<float>(resolution);
    read_ranges(f, 9, n, s.ranges);
    const size_t o = 10 + n + static_cast<size_t>(m);
    const Pose2D laser(number(f, o, "laser_x"), number(f, o + 1, "laser_y"),
                       number(f, o + 2, "laser_theta"));
    s.odometry = Pose2D(number(f, o + 3, "robot_x"), number(f, o + 4, "robot_y"),
                        wrap_angle(number(f, o + 5, "robot_theta")));
    s.sensor_pose = laser - s.odometry;
    s.timestamp = number(f, o + 11, "the timestamp");
    return s;
  }

  void parse_param(const std::vector<std::string_view>& f) {
    if (f.size() >= 2 && f[1] == "robot_frontlaser_offset") {
      if (f.size() < 3) fail("PARAM robot_frontlaser_offset without a value");
      laser_offset_ = number(f, 2, "robot_frontlaser_offset");
    }
  }

  static NoReturn find_no_return(const std::vector<RawScan>& scans) {
    float top = 0.0f;
    for (const auto& s : scans)
      for (float r : s.ranges) top = std::max(top, r);
    const float threshold = static_cast<float>(top - kCarmenNoReturnBand);
    size_t near_top = 0;
    for (const auto& s : scans)
      for (float r : s.ranges) near_top += (r >= threshold) ? 1 : 0;
    if (near_top >= 2 && threshold > 0.0f) return {threshold};
    return {std::nextafter(top, std::numeric_limits<float>::infinity())};
  }

  static std::vector<uint8_t> find_constant_beams(
      const std::vector<RawScan>& scans) {
    if (scans.size() < kCarmenConstantBeamMinScans) return {};
    const size_t n = scans[0].ranges.size();
    std::vector<uint8_t> constant(n, 1);
    for (const auto& s : scans) {
      if (s.ranges.size() != n) return {};
      for (size_t i = 0; i < n; ++i)
        if (s.ranges[i] != scans[0].ranges[i]) constant[i] = 0;
    }
    return constant;
  }

  std::string path_;
  size_t line_no_ = 0;
  double laser_offset_ = 0.0;
  std::vector<RawScan> flaser_;
  std::vector<RawScan> robotlaser_;
};

}  // namespace

hmt::Log read_carmen(const std::string& path) { return read_carmen(path, nullptr); }

hmt::Log read_carmen(const std::string& path, std::vector<Pose2D>* odometry) {
  const std::string text = detail::read_text_file(path, "CARMEN log");
  if (text.find_first_not_of(" \t\r\n") == std::string::npos)
    throw InputError("CARMEN log '" + path + "' is empty");
  CarmenParser parser(path);
  parser.parse(text);
  return parser.finish(odometry);
}

}  // namespace hmt::io

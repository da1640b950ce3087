#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
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

// What a log's PARAM lines say of its front laser (FLASER lines hold ranges
// only): its angular step (laser_front_laser_resolution, degrees) and field
// of view (laser_front_laser_fov: radians where at most 2 pi, as csail's
// 3.14159, else degrees).
struct FrontLaserParams {
  std::optional<double> resolution_deg;
  std::optional<double> fov;
};

// A FLASER scan's first bearing and step: the PARAMs' step (or their field
// of view over the beams) where they give one, centred on the robot's
// heading; where they describe a 180 degree span (to within a step: the
// SICK scanners of the classic logs, whatever the count), or say nothing,
// the count's rule above, as before. A span beyond a full turn is refused.
std::pair<double, double> flaser_angles(size_t n, const FrontLaserParams& p,
                                        const std::function<void(const std::string&)>& fail) {
  const double by_count = flaser_resolution(n);
  double step = 0.0;
  if (p.resolution_deg) {
    step = *p.resolution_deg * kDeg;
  } else if (p.fov && n > 1) {
    step = (*p.fov > 2.0 * M_PI + 1e-6 ? *p.fov * kDeg : *p.fov) / double(n - 1);
  }
  if (!(step > 0.0) || n < 2) return {-M_PI / 2.0, by_count};
  const double span = step * double(n - 1);
  if (std::fabs(span - M_PI) <= step + 1e-9) return {-M_PI / 2.0, by_count};
  if (span > 2.0 * M_PI + step + 1e-9) {
    char m[160];
    std::snprintf(m, sizeof m,
                  "FLASER scans of %zu beams %.4g degrees apart (its PARAM lines) would span "
                  "%.1f degrees, more than a full turn",
                  n, step / kDeg, span / kDeg);
    fail(m);
  }
  return {-span / 2.0, step};
}

// The two largest readings (with repeats), the first scan and the beams
// that have read the same as in it in every scan so far: what the log-wide
// decisions need, gathered one scan at a time.
struct ScanStats {
  size_t count = 0;
  float top = 0.0f;
  float second = 0.0f;
  std::vector<float> first;
  std::vector<uint8_t> constant;
  bool one_beam_count = true;

  void add(const std::vector<float>& ranges) {
    for (float r : ranges) {
      if (r > top) {
        second = top;
        top = r;
      } else if (r > second) {
        second = r;
      }
    }
    if (count == 0) {
      first = ranges;
      constant.assign(ranges.size(), 1);
    } else if (ranges.size() != first.size()) {
      one_beam_count = false;
    } else {
      for (size_t i = 0; i < ranges.size(); ++i)
        if (ranges[i] != first[i]) constant[i] = 0;
    }
    ++count;
  }

  // The no-return threshold (carmen.h): at least two readings within the
  // band of the largest one make it a no-return code.
  float max_range() const {
    const float threshold = static_cast<float>(top - kCarmenNoReturnBand);
    if (count > 0 && second >= threshold && threshold > 0.0f) return threshold;
    return std::nextafter(top, std::numeric_limits<float>::infinity());
  }

  // Beams that read one value in every scan of a long enough log.
  std::vector<uint8_t> dead_beams() const {
    if (count < kCarmenConstantBeamMinScans || !one_beam_count) return {};
    return constant;
  }
};

// Parses one line at a time; the reader (below) decides what to keep.
class CarmenParser {
 public:
  // `front_laser`: what the log's PARAMs say of its FLASER laser, as far as
  // they are known (the reader's second pass knows them all from its first).
  explicit CarmenParser(const std::string& path, FrontLaserParams front_laser = {})
      : path_(path), front_laser_(front_laser) {}

  [[noreturn]] void fail(const std::string& problem) const {
    throw InputError("CARMEN log '" + path_ + "' line " +
                     std::to_string(line_no_) + ": " + problem);
  }

  enum class Kind { kOther, kFlaser, kRobotLaser };

  // The next line; its scan into *scan for FLASER and ROBOTLASER1 lines
  // (only those of `wanted` when it is not kOther: the others are skipped
  // unparsed), a PARAM's laser offset into laser_offset().
  Kind parse_line(std::string_view line, RawScan* scan, Kind wanted = Kind::kOther) {
    ++line_no_;
    if (line.find_first_not_of(" \t\r\n\v\f") != std::string_view::npos) any_text_ = true;
    detail::split_fields(line, f_);
    if (f_.empty() || f_[0][0] == '#') return Kind::kOther;
    const std::string_view type = f_[0];
    if (wanted != Kind::kOther) {
      const Kind k = type == "FLASER"        ? Kind::kFlaser
                     : type == "ROBOTLASER1" ? Kind::kRobotLaser
                                             : Kind::kOther;
      if (k != wanted) return Kind::kOther;
    }
    if (!plausible_message_name(type))
      fail("'" + printable(type) + "' is not a CARMEN message name");
    if (type == "FLASER") {
      *scan = parse_flaser(f_);
      return Kind::kFlaser;
    }
    if (type == "ROBOTLASER1") {
      *scan = parse_robotlaser(f_);
      return Kind::kRobotLaser;
    }
    if (type == "PARAM") parse_param(f_);
    // ODOM, TRUEPOS, RAWLASER*, SYNC, ...: not needed.
    return Kind::kOther;
  }

  size_t lines() const { return line_no_; }
  bool any_text() const { return any_text_; }
  double laser_offset() const { return laser_offset_; }
  const FrontLaserParams& front_laser() const { return front_laser_; }

 private:
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
    const auto [first, step] =
        flaser_angles(n, front_laser_, [this](const std::string& m) { fail(m); });
    s.angle_min = static_cast<float>(first);
    s.angle_increment = static_cast<float>(step);
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
    // The first of each (csail states its resolution twice, alike).
    const auto angle = [&](std::string_view key, std::optional<double>* out) {
      if (f.size() < 2 || f[1] != key || *out) return;
      if (f.size() < 3) fail("PARAM " + std::string(key) + " without a value");
      const double v = number(f, 2, std::string(key).c_str());
      if (!(v > 0.0)) fail("PARAM " + std::string(key) + " is " + printable(f[2]) + ", not above 0");
      *out = v;
    };
    angle("laser_front_laser_resolution", &front_laser_.resolution_deg);
    angle("laser_front_laser_fov", &front_laser_.fov);
  }

  std::string path_;
  size_t line_no_ = 0;
  bool any_text_ = false;
  double laser_offset_ = 0.0;
  FrontLaserParams front_laser_;
  std::vector<std::string_view> f_;
};

// Two passes over the file, so that no more than a line is held: the first
// parses every line (so a damaged log fails here, before any step is handed
// out) and makes the log-wide decisions; the second hands out the steps.
class CarmenStream : public LogStream {
 public:
  explicit CarmenStream(const std::string& path)
      : LogStream(path), file_bytes_(file_size(path)) {
    CarmenParser parser(path);
    detail::LineReader in(path, "CARMEN log");
    ScanStats flaser, robotlaser;
    RawScan scan;
    std::string_view line;
    while (in.next(&line)) {
      const CarmenParser::Kind k = parser.parse_line(line, &scan);
      if (k == CarmenParser::Kind::kFlaser) flaser.add(scan.ranges);
      if (k == CarmenParser::Kind::kRobotLaser) robotlaser.add(scan.ranges);
    }
    if (!parser.any_text()) throw InputError("CARMEN log '" + path + "' is empty");
    // Logs with both carry the same scans twice; FLASER is the classic one.
    const bool use_flaser = flaser.count > 0;
    const ScanStats& stats = use_flaser ? flaser : robotlaser;
    if (stats.count == 0)
      throw InputError("CARMEN log '" + path +
                       "' holds no laser scans (no FLASER or ROBOTLASER1 "
                       "line in " + std::to_string(parser.lines()) + " lines)");
    kind_ = use_flaser ? CarmenParser::Kind::kFlaser : CarmenParser::Kind::kRobotLaser;
    scans_ = stats.count;
    max_range_ = stats.max_range();
    dead_beams_ = stats.dead_beams();
    laser_offset_ = parser.laser_offset();
    front_laser_ = parser.front_laser();
    // PARAMs no scan of the log could span fail here, before any step, even
    // where they come after the scans (the second pass applies them).
    if (use_flaser) flaser_angles(stats.first.size(), front_laser_, [&](const std::string& m) {
        throw InputError("CARMEN log '" + path + "': " + m);
      });
  }

  bool next(LogStep& out) override {
    if (!in_) {
      if (handed_ > 0) return false;  // ended
      in_ = std::make_unique<detail::LineReader>(source(), "CARMEN log");
      parser_ = std::make_unique<CarmenParser>(source(), front_laser_);
    }
    RawScan s;
    std::string_view line;
    for (;;) {
      if (!in_->next(&line)) {
        if (handed_ != scans_) changed();
        in_.reset();
        return false;
      }
      if (parser_->parse_line(line, &s, kind_) == kind_) break;
    }
    if (handed_ >= scans_) changed();
    out = LogStep();
    out.timestamp = s.timestamp;
    if (handed_ > 0) {
      out.has_odometry = true;
      out.odometry_increment = s.odometry - odometry_;
    }
    odometry_ = s.odometry;
    ++handed_;
    LaserScan& scan = out.scan;
    scan.timestamp = s.timestamp;
    scan.angle_min = s.angle_min;
    scan.angle_increment = s.angle_increment;
    scan.max_range = max_range_;
    scan.sensor_pose = s.sensor_pose.value_or(Pose2D(laser_offset_, 0, 0));
    scan.valid.resize(s.ranges.size());
    for (size_t i = 0; i < s.ranges.size(); ++i) {
      const float r = s.ranges[i];
      const bool dead = i < dead_beams_.size() && dead_beams_[i];
      // Zero, and subnormal values (below 1.2e-38 m: a zero with rounding
      // noise, not a distance a laser measures), are no readings.
      scan.valid[i] = (std::isnormal(r) && r < max_range_ && !dead) ? 1 : 0;
    }
    scan.ranges = std::move(s.ranges);
    return true;
  }

  double fraction_read() const override {
    if (!in_) return handed_ > 0 ? 1.0 : 0.0;
    if (file_bytes_ == 0) return 1.0;
    return std::min(1.0, static_cast<double>(in_->file_offset()) / static_cast<double>(file_bytes_));
  }
  std::optional<size_t> total_steps() const override { return scans_; }

  // The odometry of the step last handed out, as the log has it.
  const Pose2D& odometry() const { return odometry_; }

 private:
  static uint64_t file_size(const std::string& path) {
    std::error_code ec;
    const auto n = std::filesystem::file_size(path, ec);
    return ec ? 0 : static_cast<uint64_t>(n);
  }

  [[noreturn]] void changed() const {
    throw InputError("CARMEN log '" + source() + "' changed while it was read (" +
                     std::to_string(scans_) + " scans at first, now more or fewer)");
  }

  CarmenParser::Kind kind_ = CarmenParser::Kind::kFlaser;
  size_t scans_ = 0;
  float max_range_ = 0.0f;
  std::vector<uint8_t> dead_beams_;
  double laser_offset_ = 0.0;
  FrontLaserParams front_laser_;
  uint64_t file_bytes_ = 0;
  std::unique_ptr<detail::LineReader> in_;
  std::unique_ptr<CarmenParser> parser_;
  size_t handed_ = 0;
  Pose2D odometry_;
};

}  // namespace

std::unique_ptr<LogStream> open_carmen(const std::string& path) {
  return std::make_unique<CarmenStream>(path);
}

hmt::Log read_carmen(const std::string& path) { return read_carmen(path, nullptr); }

hmt::Log read_carmen(const std::string& path, std::vector<Pose2D>* odometry) {
  CarmenStream stream(path);
  if (odometry) odometry->clear();
  hmt::Log log;
  log.source = path;
  log.steps.reserve(*stream.total_steps());
  LogStep step;
  while (stream.next(step)) {
    if (odometry) odometry->push_back(stream.odometry());
    log.steps.push_back(std::move(step));
  }
  return log;
}

}  // namespace hmt::io

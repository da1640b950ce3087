#include "rawlog_scan.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "hmt/common/pose2d.h"

namespace hmt::io::detail {
namespace {

constexpr int64_t kTicksPerSecond = 10000000;                       // 100 ns
constexpr int64_t kUnixEpochInTicks = INT64_C(116444736000000000);  // 1601->1970

std::string beam_value(size_t beam, float value) {
  char v[32];
  std::snprintf(v, sizeof(v), "%g", static_cast<double>(value));
  return "beam " + std::to_string(beam) + " reads " + v;
}

}  // namespace

int64_t to_mrpt_ticks(double t) {
  if (!std::isfinite(t) || t < -11644473600.0 || t > 1.0e11)
    throw std::invalid_argument("timestamp " + std::to_string(t) +
                                " cannot be represented by mrpt::Clock");
  const double whole = std::floor(t);
  return static_cast<int64_t>(whole) * kTicksPerSecond +
         std::llround((t - whole) * kTicksPerSecond) + kUnixEpochInTicks;
}

double from_mrpt_ticks(int64_t ticks_since_1601) {
  if (ticks_since_1601 == 0) return 0.0;
  const int64_t ticks = ticks_since_1601 - kUnixEpochInTicks;
  // Whole seconds and the fraction separately: a double cannot hold 1e16
  // ticks exactly, but holds seconds + a sub-second part well enough.
  int64_t secs = ticks / kTicksPerSecond;
  int64_t frac = ticks % kTicksPerSecond;
  if (frac < 0) {
    frac += kTicksPerSecond;
    secs -= 1;
  }
  return static_cast<double>(secs) +
         static_cast<double>(frac) / static_cast<double>(kTicksPerSecond);
}

int64_t mrpt_now_ticks() {
  const auto since_1970 = std::chrono::duration_cast<std::chrono::nanoseconds>(
      std::chrono::system_clock::now().time_since_epoch());
  return since_1970.count() / 100 + kUnixEpochInTicks;
}

hmt::LaserScan to_laser_scan(const ScanRecord& in) {
  const size_t n = in.ranges.size();
  if (n == 0) throw std::invalid_argument("it has no beams");
  const float max_range = in.max_range;
  if (!std::isfinite(max_range) || max_range <= 0.0f)
    throw std::invalid_argument("its maxRange is " +
                                std::to_string(static_cast<double>(max_range)));

  // The beams of a 2D scanner span at most one turn (a little slack for
  // drivers that round 2 pi up).
  if (!(in.aperture >= 0.0f && double(in.aperture) <= 2.0 * M_PI + 1e-3))
    throw std::invalid_argument("its aperture is " +
                                std::to_string(static_cast<double>(in.aperture)) +
                                " rad, not in [0, 2 pi]");

  hmt::LaserScan out;
  out.timestamp = from_mrpt_ticks(in.timestamp);
  out.max_range = max_range;
  // Heading and mounting from the rotation matrix rather than from
  // yaw/pitch/roll, whose decomposition is ambiguous for a sensor mounted
  // upside down: the sensor's x axis seen from above, and whether its z axis
  // points down (then bearings are mirrored as seen from above).
  const auto& rot = in.sensor_pose.rot;
  const bool upside_down = rot[2][2] < 0.0;
  out.sensor_pose = Pose2D(in.sensor_pose.x, in.sensor_pose.y,
                           std::atan2(rot[1][0], rot[0][0]));
  if (!std::isfinite(out.sensor_pose.x) || !std::isfinite(out.sensor_pose.y) ||
      !std::isfinite(out.sensor_pose.theta) || !std::isfinite(rot[2][2]))
    throw std::invalid_argument("its sensor pose is not finite");

  // MRPT: beam i of a right-to-left scan is at -aperture/2 + i*aperture/(N-1)
  // in the sensor frame, of a left-to-right one at +aperture/2 - i*... The
  // beams are re-ordered so that bearings increase as seen from above, which
  // is what the rest of the code expects.
  const double aperture = in.aperture;
  const bool ascending = in.right_to_left != upside_down;
  if (n > 1) {
    out.angle_min = static_cast<float>(-aperture / 2.0);
    out.angle_increment = static_cast<float>(aperture / double(n - 1));
  }
  out.ranges.resize(n);
  out.valid.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const size_t src = ascending ? i : n - 1 - i;
    float r = in.ranges[src];
    bool ok = src < in.valid.size() && in.valid[src] != 0;
    if (std::isnan(r)) throw std::invalid_argument(beam_value(src, r));
    if (r < 0.0f) throw std::invalid_argument(beam_value(src, r));
    if (std::isinf(r)) {  // some drivers write +inf for "no return"
      r = max_range;
      ok = false;
    }
    out.ranges[i] = r;
    // isnormal: neither zero nor subnormal (below 1.2e-38 m, not a distance).
    out.valid[i] = (ok && std::isnormal(r) && r < max_range) ? 1 : 0;
  }
  return out;
}

ScanRecord to_scan_record(const hmt::LaserScan& in, double timestamp) {
  const size_t n = in.size();
  if (n == 0) throw std::invalid_argument("a scan has no beams");
  if (in.valid.size() != n)
    throw std::invalid_argument("a scan has " + std::to_string(n) +
                                " ranges but " +
                                std::to_string(in.valid.size()) +
                                " validity flags");
  const double inc = in.angle_increment;
  const double aperture = std::abs(inc) * double(n - 1);
  const bool right_to_left = inc >= 0.0;
  // Direction of the MRPT scan's middle, where its sensor x axis must point.
  const double centre = right_to_left ? in.angle_min + aperture / 2.0
                                      : in.angle_min - aperture / 2.0;
  ScanRecord out;
  out.ranges = in.ranges;
  out.valid.resize(n);
  for (size_t i = 0; i < n; ++i) out.valid[i] = in.valid[i] != 0 ? 1 : 0;
  out.aperture = static_cast<float>(aperture);
  out.right_to_left = right_to_left;
  out.max_range = in.max_range;
  out.sensor_pose =
      mrpt_pose3d(in.sensor_pose.x, in.sensor_pose.y, 0.0,
                  wrap_angle(in.sensor_pose.theta + centre), 0.0, 0.0);
  out.timestamp = to_mrpt_ticks(timestamp);
  return out;
}

double mrpt_wrap_to_pi(double a) {
  // mrpt::math::wrapToPi(): wrapTo2Pi(a + pi) - pi, with wrapTo2Pi by fmod.
  double b = a + M_PI;
  const bool was_negative = b < 0;
  b = std::fmod(b, 2.0 * M_PI);
  if (was_negative) b += 2.0 * M_PI;
  return b - M_PI;
}

Pose2DRecord mrpt_pose2d(double x, double y, double phi) {
  return Pose2DRecord{x, y, mrpt_wrap_to_pi(phi)};
}

Pose3DRecord mrpt_pose3d(double x, double y, double z, double yaw,
                         double pitch, double roll) {
  yaw = mrpt_wrap_to_pi(yaw);
  pitch = mrpt_wrap_to_pi(pitch);
  roll = mrpt_wrap_to_pi(roll);
  const double cy = std::cos(yaw), sy = std::sin(yaw);
  const double cp = std::cos(pitch), sp = std::sin(pitch);
  const double cr = std::cos(roll), sr = std::sin(roll);
  Pose3DRecord p;
  p.x = x;
  p.y = y;
  p.z = z;
  // CPose3D::rebuildRotationMatrix(), term by term (the order of the
  // operations decides the last bit, and the sign of zeros).
  const double rot[3][3] = {{cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr},
                            {sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr},
                            {-sp, cp * sr, cp * cr}};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) p.rot[r][c] = rot[r][c];
  return p;
}

}  // namespace hmt::io::detail

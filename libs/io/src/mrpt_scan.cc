#include "mrpt_scan.h"

#include <cmath>
#include <cstdio>
#include <cstdint>
#include <stdexcept>

#include "hmt/common/pose2d.h"

namespace hmt::io::detail {
namespace {

constexpr int64_t kTicksPerSecond = 10000000;                // 100 ns ticks
constexpr int64_t kUnixEpochInTicks = INT64_C(116444736000000000);  // 1601->1970

std::string beam_value(size_t beam, float value) {
  char v[32];
  std::snprintf(v, sizeof(v), "%g", static_cast<double>(value));
  return "beam " + std::to_string(beam) + " reads " + v;
}

}  // namespace

mrpt::Clock::time_point to_mrpt_time(double t) {
  if (!std::isfinite(t) || t < -11644473600.0 || t > 1.0e11)
    throw std::invalid_argument("timestamp " + std::to_string(t) +
                                " cannot be represented by mrpt::Clock");
  const double whole = std::floor(t);
  const auto ticks = static_cast<int64_t>(whole) * kTicksPerSecond +
                     std::llround((t - whole) * kTicksPerSecond) +
                     kUnixEpochInTicks;
  return mrpt::Clock::time_point(mrpt::Clock::duration(ticks));
}

double from_mrpt_time(mrpt::Clock::time_point t) {
  if (t == mrpt::Clock::time_point()) return 0.0;
  const int64_t ticks =
      static_cast<int64_t>(t.time_since_epoch().count()) - kUnixEpochInTicks;
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

hmt::LaserScan from_mrpt_scan(const mrpt::obs::CObservation2DRangeScan& in) {
  const size_t n = in.getScanSize();
  if (n == 0) throw std::invalid_argument("it has no beams");
  const float max_range = in.maxRange;
  if (!std::isfinite(max_range) || max_range <= 0.0f)
    throw std::invalid_argument("its maxRange is " +
                                std::to_string(static_cast<double>(max_range)));

  hmt::LaserScan out;
  out.timestamp = from_mrpt_time(in.timestamp);
  out.max_range = max_range;
  // Heading and mounting from the rotation matrix rather than from
  // yaw/pitch/roll, whose decomposition is ambiguous for a sensor mounted
  // upside down: the sensor's x axis seen from above, and whether its z axis
  // points down (then bearings are mirrored as seen from above).
  const auto rot = in.sensorPose.getRotationMatrix();
  const bool upside_down = rot(2, 2) < 0.0;
  out.sensor_pose = Pose2D(in.sensorPose.x(), in.sensorPose.y(),
                           std::atan2(rot(1, 0), rot(0, 0)));

  // MRPT: beam i of a right-to-left scan is at -aperture/2 + i*aperture/(N-1)
  // in the sensor frame, of a left-to-right one at +aperture/2 - i*... The
  // beams are re-ordered so that bearings increase as seen from above, which
  // is what the rest of the code expects.
  const double aperture = in.aperture;
  const bool ascending = in.rightToLeft != upside_down;
  if (n > 1) {
    out.angle_min = static_cast<float>(-aperture / 2.0);
    out.angle_increment = static_cast<float>(aperture / double(n - 1));
  }
  out.ranges.resize(n);
  out.valid.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const size_t src = ascending ? i : n - 1 - i;
    float r = in.getScanRange(src);
    bool ok = in.getScanRangeValidity(src);
    if (std::isnan(r)) throw std::invalid_argument(beam_value(src, r));
    if (r < 0.0f) throw std::invalid_argument(beam_value(src, r));
    if (std::isinf(r)) {  // some drivers write +inf for "no return"
      r = max_range;
      ok = false;
    }
    out.ranges[i] = r;
    out.valid[i] = (ok && r > 0.0f && r < max_range) ? 1 : 0;
  }
  return out;
}

void to_mrpt_scan(const hmt::LaserScan& in, double timestamp,
                  mrpt::obs::CObservation2DRangeScan& out) {
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
  out.resizeScan(n);
  for (size_t i = 0; i < n; ++i) {
    out.setScanRange(i, in.ranges[i]);
    out.setScanRangeValidity(i, in.valid[i] != 0);
  }
  out.aperture = static_cast<float>(aperture);
  out.rightToLeft = right_to_left;
  out.maxRange = in.max_range;
  out.sensorPose = mrpt::poses::CPose3D(
      in.sensor_pose.x, in.sensor_pose.y, 0.0,
      wrap_angle(in.sensor_pose.theta + centre), 0.0, 0.0);
  out.sensorLabel = "LASER";
  out.timestamp = to_mrpt_time(timestamp);
}

}  // namespace hmt::io::detail

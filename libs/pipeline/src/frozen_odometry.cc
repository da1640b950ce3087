#include "frozen_odometry.h"

#include <cmath>
#include <cstdio>

#include "hmt/area/scan_sso.h"
#include "hmt/common/error.h"

namespace hmt::pipeline {

double FrozenOdometryCheck::changed_share(const LaserScan& a, const LaserScan& b) {
  if (a.size() != b.size()) return -1.0;
  size_t both = 0, changed = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    if (!area::is_valid_return(a, i) || !area::is_valid_return(b, i)) continue;
    ++both;
    const double ra = a.ranges[i], rb = b.ranges[i];
    changed += std::fabs(ra - rb) > kChangedRange + kChangedRangeShare * std::min(ra, rb);
  }
  if (both < kMinBeams) return -1.0;
  return static_cast<double>(changed) / static_cast<double>(both);
}

void FrozenOdometryCheck::add(const LogStep& step, size_t index, const std::string& source) {
  if (have_reference_) moved_ = moved_ + step.odometry_increment;
  if (!have_reference_ || std::hypot(moved_.x, moved_.y) >= kStillDistance ||
      std::fabs(moved_.theta) >= kStillAngle) {
    reference_ = step.scan;
    reference_index_ = index;
    moved_ = Pose2D();
    have_reference_ = true;
    return;
  }
  const double share = changed_share(reference_, step.scan);
  if (!(share > kChangedShare)) return;
  char m[256];
  std::snprintf(m, sizeof m,
                "%.0f %% of the laser's returns changed by more than %.1f m since step %zu, "
                "but the odometry moved the robot only %.3f m and %.3f rad",
                100.0 * share, kChangedRange, reference_index_, std::hypot(moved_.x, moved_.y),
                std::fabs(moved_.theta));
  throw InputError("log '" + source + "' step " + std::to_string(index) + ": " + m +
                   ": the odometry is frozen or missing (hmt-slam needs the robot's "
                   "odometry: each scan's match starts from it)");
}

}  // namespace hmt::pipeline

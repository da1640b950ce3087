#include "hmt/metric_slam/matching_range.h"

#include <algorithm>
#include <cmath>

#include "nearest_spacing.h"

namespace hmt::metric_slam {

void RangeSample::add(const LaserScan& scan, const Pose2D& odometry_increment) {
  if (complete()) return;
  ++read_;
  readings_read_ += scan.size();
  moved_ = moved_ + odometry_increment;
  if (scans_ > 0 &&
      short_of_nearest_mark(moved_, odometry_increment, kRangeSampleSpacing, kRangeSampleTurn))
    return;
  moved_ = Pose2D();
  ++scans_;
  for (size_t i = 0; i < scan.size(); ++i) {
    const float r = scan.ranges[i];
    if (i < scan.valid.size() && scan.valid[i] && std::isfinite(r) && r > 0.0f &&
        r < scan.max_range)
      ranges_.push_back(r);
  }
}

bool RangeSample::complete() const {
  return scans_ >= kRangeSampleScans || ranges_.size() >= kRangeSampleReturns ||
         readings_read_ >= kRangeSamplePeekReadings;
}

double RangeSample::quantile() const {
  if (ranges_.empty()) return 0.0;
  std::vector<float> r = ranges_;
  const size_t k = static_cast<size_t>(
      std::ceil(kMatchingRangeQuantile * static_cast<double>(r.size()))) - 1;
  std::nth_element(r.begin(), r.begin() + static_cast<std::ptrdiff_t>(k), r.end());
  return r[k];
}

double RangeSample::matching_range() const {
  return std::max(kMinMatchingRange, std::ceil(quantile()));
}

bool resolve_matching_range(MatcherOptions& matcher, grid::InsertionOptions& insertion,
                            const RangeSample& sample) {
  if (!matcher.range_from_scans) return false;
  matcher.max_range = sample.matching_range();
  if (insertion.range_from_matcher) insertion.max_range = matcher.max_range;
  return true;
}

}  // namespace hmt::metric_slam

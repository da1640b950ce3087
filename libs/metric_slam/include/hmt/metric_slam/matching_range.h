// How far the scan matcher looks: `[scan_matcher] max_range = auto`, derived
// from the log's own ranges.
//
// Why. The matcher (and the grids, whose insertion range follows it) use
// the returns up to max_range. Indoors nearly every return lies within 20 m
// (80 % within 4-13 m on the shared logs), so a 20 m cap costs nothing and
// keeps the long rays, most of the insertion cost, out. Outdoors it is the
// other way round: building fronts across a street or a square lie 20-60 m
// away and most returns are beyond 20 m; cut there, a scan keeps only the
// trees and posts near the path, sparse and repetitive, and the matcher
// snaps to wrong headings (on a simulated 1.6 km campus: 35 degrees within
// five scans, worse than the odometry alone).
//
// The rule. max_range = the range within which kMatchingRangeQuantile of
// the valid returns lie, over the first scans of the log (up to
// kRangeSampleScans scans or kRangeSampleReturns returns), rounded up to a
// whole metre and never below kMinMatchingRange. The matcher then sees the
// band that holds most of what the sensor sees; the farthest fifth, sparse
// and the most sensitive to beam divergence and grazing angles, stays out.
// Indoors the rule gives the floor, 20 m, as before.
#pragma once

#include <cstddef>
#include <vector>

#include "hmt/common/sensor_data.h"
#include "hmt/grid/scan_insertion.h"
#include "hmt/metric_slam/scan_matcher.h"

namespace hmt::metric_slam {

constexpr double kMinMatchingRange = 20.0;      // [m]
constexpr double kMatchingRangeQuantile = 0.8;
constexpr size_t kRangeSampleScans = 100;
constexpr size_t kRangeSampleReturns = 20000;

// The valid returns of the first scans of a log.
class RangeSample {
 public:
  // Adds the valid returns (flagged valid, finite, 0 < r < the scan's
  // max_range) of one more scan; ignored once complete().
  void add(const LaserScan& scan);
  // kRangeSampleScans scans or kRangeSampleReturns returns taken.
  bool complete() const;
  size_t scans() const { return scans_; }
  size_t returns() const { return ranges_.size(); }
  // The kMatchingRangeQuantile quantile of the returns (0 without any).
  double quantile() const;
  // The rule: max(kMinMatchingRange, quantile() rounded up to a metre).
  double matching_range() const;

 private:
  std::vector<float> ranges_;
  size_t scans_ = 0;
};

// With matcher.range_from_scans, sets matcher.max_range to
// sample.matching_range() (and insertion.max_range with it when
// insertion.range_from_matcher) and returns true; returns false otherwise.
bool resolve_matching_range(MatcherOptions& matcher, grid::InsertionOptions& insertion,
                            const RangeSample& sample);

}  // namespace hmt::metric_slam

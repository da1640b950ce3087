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
// the valid returns lie, over the log's first scans a metre apart (up to
// kRangeSampleScans scans or kRangeSampleReturns returns), rounded up to a
// whole metre and never below kMinMatchingRange. The matcher then sees the
// band that holds most of what the sensor sees; the farthest fifth, sparse
// and the most sensitive to beam divergence and grazing angles, stays out.
// Indoors the rule gives the floor, 20 m, as before.
//
// A metre apart, not the first scans whatever their spacing: the sample is
// then the first 100 m of the path, whether the log holds a scan a metre
// (the shared logs, thinned) or one every 10 cm (a laser recorded at 10 Hz,
// where the first 100 scans are the first 10 m: one street corner). On the
// simulated campus recorded every 10 cm the first 100 scans gave 34-51 m
// where the same drive a scan a metre gives 46-64 m, and its maps were
// 0.6-3.0 m off (0.1-1.4 m with the metre-spaced sample; the drive a scan
// a metre: 0.1-2.4 m). Spaced as the filter spaces its updates:
// the scan nearest each metre (kRangeSampleSpacing less half the scan's
// own step) or each kRangeSampleTurn of turn. A robot standing still adds
// nothing, and the scans read for the sample are held until the run takes
// them: at most kRangeSamplePeekReadings readings are read (about 10 MB of
// scans: 11 000 scans of 181 beams, 1 850 of 1 081 beams).
#pragma once

#include <cstddef>
#include <vector>

#include "hmt/common/pose2d.h"
#include "hmt/common/sensor_data.h"
#include "hmt/grid/scan_insertion.h"
#include "hmt/metric_slam/scan_matcher.h"

namespace hmt::metric_slam {

constexpr double kMinMatchingRange = 20.0;      // [m]
constexpr double kMatchingRangeQuantile = 0.8;
constexpr size_t kRangeSampleScans = 100;
constexpr size_t kRangeSampleReturns = 20000;
constexpr double kRangeSampleSpacing = 1.0;  // [m]
constexpr double kRangeSampleTurn = 0.5;     // [rad]
constexpr size_t kRangeSamplePeekReadings = 2000000;

// The valid returns of the first scans of a log, a metre apart.
class RangeSample {
 public:
  // The next scan of the log and the odometry's motion from the scan
  // before (zero for the first). The first scan, and each one nearest a
  // metre or half a radian on from the last one taken, adds its valid
  // returns (flagged valid, finite, 0 < r < the scan's max_range); the
  // others add nothing. Ignored once complete().
  void add(const LaserScan& scan, const Pose2D& odometry_increment);
  // kRangeSampleScans scans or kRangeSampleReturns returns taken, or
  // kRangeSamplePeekReadings readings read (taken or not).
  bool complete() const;
  // Scans taken into the sample, and scans read (taken or not).
  size_t scans() const { return scans_; }
  size_t read() const { return read_; }
  size_t returns() const { return ranges_.size(); }
  // The kMatchingRangeQuantile quantile of the returns (0 without any).
  double quantile() const;
  // The rule: max(kMinMatchingRange, quantile() rounded up to a metre).
  double matching_range() const;

 private:
  std::vector<float> ranges_;
  size_t scans_ = 0, read_ = 0, readings_read_ = 0;
  Pose2D moved_;  // since the last scan taken
};

// With matcher.range_from_scans, sets matcher.max_range to
// sample.matching_range() (and insertion.max_range with it when
// insertion.range_from_matcher) and returns true; returns false otherwise.
bool resolve_matching_range(MatcherOptions& matcher, grid::InsertionOptions& insertion,
                            const RangeSample& sample);

}  // namespace hmt::metric_slam

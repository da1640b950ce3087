// The paper's check of R against localization (003 section 8.1, Fig. 2-3),
// on a real map with this project's scan matcher in place of the sonar line
// matcher: at sampled free cells, the scan the robot would take there is
// simulated from the map itself (a ray cast per beam); the matcher
// (metric_slam::ScanMatcher::optimize, the [scan_matcher] options of a run)
// starts from a pose offset by offset_min to offset_max metres in a random
// direction and up to angle_offset in heading, and the distance from its
// result to the true pose is the localization error. A good R is high where
// the error is low: Spearman's rank correlation between R and the error
// should be negative.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hmt/common/config.h"
#include "hmt/grid/scan_insertion.h"
#include "hmt/islands/distinctiveness.h"
#include "hmt/islands/occupancy_raster.h"
#include "hmt/metric_slam/scan_matcher.h"

namespace hmt::islands {

struct CheckOptions {
  int samples = 1000;            // free cells (with an R) sampled
  double offset_min = 0.10;      // [m] the starting pose's offset ...
  double offset_max = 0.15;      // [m] ... uniform in [min, max]
  double angle_offset = 3.0;     // [deg] heading offset, uniform in +-this
  double field_of_view = 180.0;  // [deg] of the simulated laser ...
  int beams = 181;               // ... with this many beams ...
  double max_range = 8.0;        // [m] ... returning nothing beyond this
  uint64_t seed = 1;             // of the samples and offsets
  void load(Config& cfg, const std::string& section = "islands_check");
};

struct CheckSample {
  double x = 0.0, y = 0.0, heading = 0.0;  // the true pose, map frame
  double r = 0.0;                          // R at its cell
  double error_xy = 0.0;                   // [m] matcher result to truth
  double error_theta = 0.0;                // [rad]
};

struct CheckResult {
  std::vector<CheckSample> samples;
  double spearman = 0.0;  // rank correlation of R and error_xy
};

// The map as the matcher reads it: occupied cells at the insertion's
// clamped log-odds with one hit at their centre, free cells at its negative.
grid::OccupancyGrid matcher_grid(const OccupancyRaster& map, const grid::InsertionOptions& ins);

CheckResult localization_check(const OccupancyRaster& map, const DistinctivenessMap& d,
                               const CheckOptions& options,
                               const metric_slam::MatcherOptions& matcher,
                               const grid::InsertionOptions& insertion);

// Spearman's rank correlation (ties get their mean rank); 0 for fewer than
// two values or a constant one.
double spearman(const std::vector<double>& a, const std::vector<double>& b);

// localization_check.csv: x,y,heading,R,error_xy,error_theta.
void write_check_csv(const std::string& path, const CheckResult& result);

}  // namespace hmt::islands

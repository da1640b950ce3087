// The "latest observations" a topological transition is judged on: the scans
// of the keyframes that form the new area, gathered into one point set in the
// robot frame at the moment of the decision.
#pragma once

#include <vector>

#include "hmt/common/pose2d.h"
#include "hmt/common/sensor_data.h"
#include "hmt/metric_slam/scan_points.h"

namespace hmt::tsbi {

struct PosedScan {
  Pose2D pose;  // where the scan was taken, in any frame shared with `now`
  const LaserScan* scan = nullptr;
};

// A point set that stands for more points than it holds: log-likelihoods
// computed on `points` are multiplied by `scale` (all points / points kept),
// as the metric filter's lattice does with its beam subset.
struct Observations {
  metric_slam::ScanPoints points;
  double scale = 1.0;
  // How much the points weigh (TransitionModel): evidence_cell > 0, the
  // size (m) of the cells counted in surface_cells, the distinct cells all
  // the end points (not only those kept) fall in; the points then stand for
  // surface_cells pieces of evidence. evidence_cell 0: not counted, and
  // every return counts (scale). Set together by gather_observations(), so
  // the weighting always follows how the observations were gathered.
  double evidence_cell = 0.0;
  size_t surface_cells = 0;
  // The scans themselves, posed relative to `now` (for the area check).
  std::vector<PosedScan> scans;
};

// Every scan's end points (and free probes) re-expressed from `now`, then at
// most `max_points` of them, evenly spread. `free_step` is the probe's
// distance back along the beam (the grid resolution). `evidence_cell` > 0:
// also counts the distinct cells of that size (m) the end points fall in.
Observations gather_observations(const std::vector<PosedScan>& scans,
                                 const Pose2D& now, double max_range,
                                 double free_step, int max_points, double evidence_cell = 0.0);

}  // namespace hmt::tsbi

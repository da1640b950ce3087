// The field-of-view experiment (000 Sec. 6.2): the same route partitioned
// from the scans of sensors of different fields of view. The keyframes'
// scan SSO (fixed-delta point matching, 001 Eq. 16-18) and the recursive
// min-Ncut partition are those of the area library (group_keyframes); only
// the sensor changes. The paper's finding to reproduce: the narrower the
// field of view, the more areas (4 for two laser scanners covering ~360
// degrees, 10 for a ~65-degree stereo camera).
#pragma once

#include <string>
#include <vector>

#include "hmt/area/area_options.h"
#include "hmt/experiments/building_sim.h"

namespace hmt::experiments {

struct FovOptions {
  double step = 0.5;                   // [m] between keyframes
  double turn_step = 30.0 * M_PI / 180.0;  // [rad] between keyframes turning in place
  std::vector<double> taus = {1.0};
  area::AreaOptions area;  // SSO (delta ...), split method; partition.tau is
                           // replaced by each of `taus`
  void validate() const;
};

struct FovResult {
  std::string sensor;
  double fov_deg = 0.0;
  int beams = 0;
  double max_range = 0.0;
  double tau = 0.0;
  int keyframes = 0;
  long edges = 0;            // stored SSO edges (pairs with SSO >= min_sso)
  double mean_degree = 0.0;  // mean sum of SSO weights per keyframe
  int areas = 0;
  std::vector<int> labels;   // area of each keyframe
  double seconds = 0.0;      // SSO matrix and partition, this sensor and tau
};

// One result per (sensor, tau), sensors in the given order.
std::vector<FovResult> run_field_of_view(const World& world,
                                         const std::vector<Pose2D>& poses,
                                         const std::vector<RangeSensor>& sensors,
                                         const FovOptions& options);

}  // namespace hmt::experiments

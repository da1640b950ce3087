// The `hmt-slam run` job: a whole log through the HMT-SLAM estimator
// (hybrid::HybridFilter), then the global map, the topology and what the
// filter did, written into the output folder:
//   map.png, map.pgm + map.yaml   global occupancy grid (areas drawn at their
//                                 globally consistent poses)
//   map_topology.png              the same with area ids, arcs and 95%
//                                 ellipses (x ellipse_scale)
//   areas/area_<id>.png           each area's local map
//   hmt_map.bin                   the most probable hypothesis's HMT map and
//                                 topological path (topology::save_topology)
//   topology.json, topology.dot   areas (global pose, covariance), arcs
//   trajectory.tum                the best path in global coordinates
//   topological_pmf.csv           P(current area) at every step (Eq. 14)
//   tsbi_events.csv               every transition evaluated: outcomes, F, p
//   summary.json, config_effective.ini
#pragma once

#include <string>

#include "hmt/common/config.h"
#include "hmt/common/sensor_data.h"
#include "hmt/pipeline/metric_job.h"

namespace hmt::pipeline {

struct HmtJobSummary {
  size_t scans = 0;
  double wall_time_s = 0.0;
  size_t peak_rss_bytes = 0;
  size_t areas = 0;
  size_t arcs = 0;
  size_t loop_closures = 0;
  Pose2D final_pose;  // global frame (area 1's)
  std::string map_png;
};

HmtJobSummary run_hmt_job(const JobOptions& opt, const Log& log, const Config& cfg,
                          const std::string& out_dir, bool show_progress);

}  // namespace hmt::pipeline

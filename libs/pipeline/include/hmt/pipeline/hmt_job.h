// The `hmt-slam run` job: a log through the HMT-SLAM estimator
// (hybrid::HybridFilter), then the global map, the topology and what the
// filter did, written into the output folder:
//   map.png, map.pgm + map.yaml   global occupancy grid (areas drawn at their
//                                 globally consistent poses)
//   map_topology.png              the same with area ids, arcs and 95%
//                                 ellipses (x ellipse_scale)
//   areas/area_<id>.png           each area's local map
//   hmt_map.bin                   every hypothesis's HMT map, path and robot
//                                 pose: what `resume` continues from
//                                 (topology::save_session)
//   topology.json, topology.dot   areas (global pose, covariance), arcs
//   trajectory.tum                the best path in global coordinates
//   topological_pmf.csv           P(current area) at every step (Eq. 14)
//   tsbi_events.csv               every transition evaluated: outcomes, F, p
//   tsbi_candidates.csv           every known area each event weighed or ruled
//                                 out, and why (hmt_outputs.h)
//   summary.json, config_effective.ini
//   report/index.html ...         with --report: the HTML report (report.h)
#pragma once

#include <string>

#include "hmt/common/config.h"
#include "hmt/common/sensor_data.h"
#include "hmt/pipeline/input_steps.h"
#include "hmt/pipeline/metric_job.h"
#include "hmt/topology/topology_file.h"

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
  std::string report_html;  // with --report (OutputOptions::report): report/index.html
};

// The log is read from `steps` as the run goes, so that its length does not
// bound memory: the job keeps each step's timestamp and odometry, and after
// the run reads the log again through `reopen` (the same selection,
// opt.input) for the keyframes' scans the global map is drawn from
// (src/kept_steps.h); a log that changed between the two readings is an
// InputError.
// With `resume_from`, continues that saved run with `steps` as the log that
// follows it (steps numbered on; outputs cover the new steps).
// With `checkpoint`, continues the interrupted run that wrote it
// (hmt/checkpoint/checkpoint.h): `steps` is that run's whole log, `opt` and
// `cfg` its configuration; the outputs are those of the whole run. Throws
// InputError if the log does not begin with the steps the checkpoint holds.
//
// OUT/checkpoint.bin is written every [output] checkpoint_every scans and
// when SIGINT / SIGTERM arrives (stop_signal.h; the job then throws
// InterruptedError), and removed once the run's outputs are written.
HmtJobSummary run_hmt_job(const JobOptions& opt, InputSteps& steps, const LogOpener& reopen,
                          const Config& cfg, const std::string& out_dir, bool show_progress,
                          const topology::Session* resume_from = nullptr,
                          const std::string& checkpoint = "");

}  // namespace hmt::pipeline

// The `hmt-slam run` job for the metric layer: a whole log through the
// RBPF grid SLAM filter, then the map, trajectory, effective configuration
// and a summary written into the output folder.
#pragma once

#include <string>

#include "hmt/common/config.h"
#include "hmt/common/sensor_data.h"
#include "hmt/area/area_options.h"
#include "hmt/framework/framework_options.h"
#include "hmt/global_map/global_map_options.h"
#include "hmt/grouping/grouping_options.h"
#include "hmt/hybrid/hybrid_options.h"
#include "hmt/io/rosbag.h"
#include "hmt/islands/islands_options.h"
#include "hmt/islands/localization_check.h"
#include "hmt/metric_slam/rbpf_options.h"

namespace hmt::pipeline {

struct InputOptions {
  std::string log;     // path; relative paths are taken from the config file's folder
  int first_step = 0;  // steps of the log skipped before the first one used
  int max_steps = 0;   // 0 = the whole log
  // The most the odometry may move the robot between two scans (m): the
  // shipped logs' largest step is 1.7 m; a larger one is a broken odometry
  // (a reset, a wrapped counter), which no motion model can absorb.
  double max_step_motion = 10.0;
  io::BagOptions bag;  // which topics and frames of a ROS bag
  void load(Config& cfg, const std::string& config_dir);
  // The steps this selects (first_step on, at most max_steps). Throws
  // InputError naming the step for odometry that moves more than
  // max_step_motion in one step.
  Log select(Log log) const;
};

struct OutputOptions {
  bool png = true;
  bool pgm = true;
  int map_margin = 10;  // cells of unknown border around the map image
  // Not an INI key: `hmt-slam run --report` (the HTML report, report.h).
  bool report = false;
  // map.gridmap.gz and keyframes.simplemap for MRPT's tools (hmt run only;
  // src/mrpt_map_outputs.h)
  bool mrpt_maps = false;
  // hmt-slam run: write OUT/checkpoint.bin every this many scans (0: only
  // on SIGINT / SIGTERM); deterministic mode only (hmt/checkpoint).
  int checkpoint_every = 500;
  void load(Config& cfg);
};

struct JobOptions {
  InputOptions input;
  OutputOptions output;
  metric_slam::RbpfOptions rbpf;
  area::AreaOptions area;
  grouping::GroupingOptions grouping;
  tsbi::TsbiOptions tsbi;
  tlca::TlcaOptions tlca;
  hybrid::HybridOptions hybrid;
  framework::FrameworkOptions framework;
  global_map::GlobalMapOptions global_map;
  // `hmt-slam islands`: the distinctiveness measure and the islands.
  islands::IslandsOptions islands;
  // `hmt-slam islands --check`: R against the scan matcher's error.
  islands::CheckOptions islands_check;
  // The options of the HMT-SLAM estimator, gathered from the above.
  hybrid::HmtOptions hmt() const { return {rbpf, area, tsbi, tlca, hybrid}; }
};

// Reads every option of every component from `cfg`, then fails on any key
// no component read. A relative input path is taken from the folder of the
// layer that set it (Config::dir_of), or else from `config_dir`.
JobOptions load_job_options(Config& cfg, const std::string& config_dir);

struct JobSummary {
  size_t scans = 0;
  double wall_time_s = 0.0;
  size_t peak_rss_bytes = 0;
  Pose2D final_pose;
  std::string map_png;  // path of the map image, if written
};

class InputSteps;  // input_steps.h

// Runs the filter over `steps`, read as it goes (only their timestamps are
// kept), and writes the outputs into `out_dir`. `show_progress` draws
// progress on stderr. Throws InputError for a log without scans, and
// whatever the reader throws.
JobSummary run_metric_job(const JobOptions& opt, InputSteps& steps,
                          const Config& cfg, const std::string& out_dir,
                          bool show_progress);

}  // namespace hmt::pipeline

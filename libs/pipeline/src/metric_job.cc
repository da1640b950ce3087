#include "hmt/pipeline/metric_job.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "hmt/common/error.h"
#include "hmt/common/files.h"
#include "hmt/common/progress.h"
#include "hmt/common/resources.h"
#include "hmt/grid/map_export.h"
#include "hmt/io/tum.h"
#include "hmt/pipeline/input_steps.h"
#include "hmt/pipeline/metric_summary.h"
#include "hmt/metric_slam/grid_rbpf.h"

namespace hmt::pipeline {
namespace fs = std::filesystem;

void InputOptions::load(Config& cfg, const std::string& config_dir) {
  log = cfg.get_string("input", "log", log);
  first_step = cfg.get_int("input", "first_step", first_step);
  max_steps = cfg.get_int("input", "max_steps", max_steps);
  max_step_motion = cfg.get_double("input", "max_step_motion", max_step_motion);
  require(first_step >= 0, "input", "first_step", ">= 0");
  require(max_steps >= 0, "input", "max_steps", ">= 0");
  require(max_step_motion > 0.0, "input", "max_step_motion", "> 0");
  bag.load(cfg, "input");
  // Relative to the folder of the layer that set it (a --config file's, the
  // built-in defaults' config/), else to `config_dir`.
  const std::string own_dir = cfg.dir_of("input", "log");
  const std::string& dir = own_dir.empty() ? config_dir : own_dir;
  if (!log.empty() && fs::path(log).is_relative() && !dir.empty())
    log = (fs::path(dir) / log).lexically_normal().string();
}

Log InputOptions::select(Log log) const {
  InputSteps steps(io::stream_of(std::move(log)), *this);
  return io::drain(steps);
}

void OutputOptions::load(Config& cfg) {
  png = cfg.get_bool("output", "png", png);
  pgm = cfg.get_bool("output", "pgm", pgm);
  map_margin = cfg.get_int("output", "map_margin", map_margin);
  mrpt_maps = cfg.get_bool("output", "mrpt_maps", mrpt_maps);
  checkpoint_every = cfg.get_int("output", "checkpoint_every", checkpoint_every);
  require(checkpoint_every >= 0, "output", "checkpoint_every", ">= 0");
  require(map_margin >= 0 && map_margin <= 1000, "output", "map_margin", "in [0, 1000]");
}

JobOptions load_job_options(Config& cfg, const std::string& config_dir) {
  JobOptions o;
  o.input.load(cfg, config_dir);
  o.output.load(cfg);
  o.rbpf.load(cfg);
  o.area.load(cfg, "area");
  o.grouping.load(cfg, "grouping");
  o.tsbi.load(cfg, "tsbi");
  o.tlca.load(cfg, "tlca");
  o.hybrid.load(cfg, "hmt");
  o.framework.load(cfg, "framework");
  o.global_map.load(cfg, "global_map");
  o.islands.load(cfg, "islands");
  o.islands_check.load(cfg, "islands_check");
  // The graph's keyframes are the area abstraction's.
  o.global_map.graph.keyframe_distance = o.hybrid.keyframe_distance;
  o.global_map.graph.keyframe_angle = o.hybrid.keyframe_angle;
  cfg.check_all_used();
  return o;
}

JobSummary run_metric_job(const JobOptions& opt, InputSteps& steps,
                          const Config& cfg, const std::string& out_dir,
                          bool show_progress) {
  const auto t0 = std::chrono::steady_clock::now();
  make_directories(out_dir);
  // The configuration first: a run that fails later still says what it used.
  write_text_atomically(out_dir + "/config_effective.ini", cfg.effective_ini());
  if (!steps.peek()) throw InputError(steps.source() + ": the log has no scans");

  metric_slam::GridRbpf filter(opt.rbpf);
  // The total when the reader knows it, else progress by the share read.
  Progress progress("scans", steps.total_steps().value_or(0));
  progress.set_enabled(show_progress);
  char extra[64];
  // The log is read as the filter goes; only the timestamps are kept.
  std::vector<double> stamps;
  LogStep step;
  while (steps.next(step)) {
    filter.process(step);
    stamps.push_back(step.timestamp);
    std::snprintf(extra, sizeof extra, "ESS %.1f/%d", filter.ess(), opt.rbpf.particles);
    progress.set_fraction(steps.fraction_read());
    progress.update(stamps.size(), extra);
  }
  progress.finish();
  const size_t n = stamps.size();

  const metric_slam::Particle& best = filter.best();
  std::vector<io::StampedPose> traj;
  traj.reserve(best.estimates.size());
  for (size_t i = 0; i < best.estimates.size(); ++i)
    traj.push_back({stamps[i], best.estimates[i]});

  JobSummary sum;
  sum.scans = n;
  sum.final_pose = best.pose;
  io::write_tum(out_dir + "/trajectory.tum", traj);
  const grid::MapImage img = grid::render(best.map, opt.output.map_margin);
  if (opt.output.png) {
    sum.map_png = out_dir + "/map.png";
    grid::write_png(img, sum.map_png);
  }
  if (opt.output.pgm) grid::write_pgm_yaml(img, out_dir + "/map");

  sum.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  sum.peak_rss_bytes = peak_rss_bytes();
  nlohmann::json j;
  j["input"] = steps.source();
  j["scans"] = sum.scans;
  j["timestamps_not_increasing"] = steps.clock_faults().count;
  j["particles"] = opt.rbpf.particles;
  j["wall_time_s"] = sum.wall_time_s;
  j["peak_rss_mb"] = static_cast<double>(sum.peak_rss_bytes) / (1024.0 * 1024.0);
  j["map_memory_mb"] = static_cast<double>(filter.map_memory_bytes()) / (1024.0 * 1024.0);
  j["final_pose"] = {{"x", best.pose.x}, {"y", best.pose.y}, {"theta", best.pose.theta}};
  const nlohmann::json counts = metric_summary(filter.stats());
  j.update(counts);
  j["final_ess"] = filter.ess();
  write_text_atomically(out_dir + "/summary.json", j.dump(2) + "\n");
  warn_if_scans_did_not_match(counts);
  steps.warn_if_clock_faults();
  return sum;
}

}  // namespace hmt::pipeline

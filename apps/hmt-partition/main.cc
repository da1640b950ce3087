// hmt-partition: the offline grouping tool of 001 Sec. IV. Argument parsing
// only; the work is done by hmt_grouping.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "hmt/common/config.h"
#include "hmt/common/error.h"
#include "hmt/grouping/grouping_options.h"
#include "hmt/grouping/partition_job.h"
#include "hmt/pipeline/default_config.h"
#include "hmt/pipeline/metric_job.h"
#include "hmt/version.h"

namespace {

struct Args {
  std::vector<std::string> configs;
  std::string input, poses, out;
  std::vector<std::string> sets;
  std::string keyframe_distance, keyframe_angle;  // empty: from the config
  bool quiet = false;
};

// CLI11 check: a finite number >= 0, kept as the user wrote it.
std::string non_negative(std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v) || v < 0.0)
    return "must be a number >= 0, not '" + text + "'";
  return "";
}

int run(const Args& a) {
  // The built-in defaults (config/default.ini), each --config, then --set;
  // the keyframe flags are overrides like --set, so that the effective
  // configuration records them.
  std::vector<std::string> sets = a.sets;
  if (!a.keyframe_distance.empty())
    sets.push_back("grouping.keyframe_distance=" + a.keyframe_distance);
  if (!a.keyframe_angle.empty()) sets.push_back("grouping.keyframe_angle=" + a.keyframe_angle);
  hmt::Config cfg = hmt::pipeline::layered_config(a.configs, sets);
  const hmt::pipeline::JobOptions job = hmt::pipeline::load_job_options(cfg, "");
  hmt::grouping::PartitionJobOptions opt;
  opt.grouping = job.grouping;
  opt.area = job.area;
  opt.local_maps.resolution = job.rbpf.resolution;
  opt.local_maps.insertion = job.rbpf.insertion;
  opt.local_maps.matcher = job.rbpf.matcher;
  opt.map_margin = job.output.map_margin;
  opt.write_pgm = job.output.pgm;
  opt.max_steps = static_cast<size_t>(job.input.max_steps);

  hmt::grouping::PartitionRequest req;
  req.log_path = a.input.empty() ? job.input.log : a.input;
  req.bag = job.input.bag;
  if (req.log_path.empty())
    throw hmt::UsageError("no input log: give --input or set [input] log");
  req.poses_path = a.poses;
  req.out_dir = a.out;
  req.effective_config = cfg.effective_ini();
  req.show_progress = !a.quiet;
  const auto s = hmt::grouping::run_partition(opt, req);
  std::printf("%zu scans, %zu keyframes, %zu groups, %zu arcs\n", s.scans,
              s.keyframes, s.groups, s.arcs);
  std::printf("grouping: %.3f s (%.3f s per 100 keyframes); total %.2f s\n",
              s.grouping_s, s.keyframes ? 100.0 * s.grouping_s / s.keyframes : 0.0,
              s.total_s);
  std::printf("outputs in: %s\n", a.out.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "hmt-partition: group a log's scans into areas by sensed-space overlap and "
      "normalized cuts, with one local map per group and the topological map "
      "joining them"};
  Args a;
  app.set_version_flag("--version", hmt::version_string("hmt-partition"));
  app.add_option("--config,-c", a.configs,
                 "INI file layered on the built-in defaults (config/default.ini); "
                 "repeatable, later files win");
  app.add_option("--input,-i", a.input,
                 "log (.rawlog, .log, .log.gz); overrides [input] log");
  app.add_option("--poses,-p", a.poses,
                 "trajectory: TUM (t x y z qx qy qz qw) or 't x y theta', gzip or "
                 "not; a scan takes the pose nearest in time within "
                 "[grouping] pose_time_tolerance, others are skipped. Default: odometry");
  app.add_option("--out,-o", a.out, "output folder")->required();
  app.add_option("--set", a.sets, "override a key: SECTION.key=value (repeatable)");
  app.add_option("--keyframe-distance", a.keyframe_distance,
                 "metres between keyframes; overrides [grouping] keyframe_distance (default 0.5)")
      ->type_name("METRES")
      ->check(CLI::Validator(non_negative, ""));
  app.add_option("--keyframe-angle", a.keyframe_angle,
                 "radians between keyframes; overrides [grouping] keyframe_angle (default 0.5)")
      ->type_name("RADIANS")
      ->check(CLI::Validator(non_negative, ""));
  app.add_flag("--quiet,-q", a.quiet, "no progress output");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : static_cast<int>(hmt::ExitCode::kUsage);
  }
  try {
    return run(a);
  } catch (const hmt::Error& e) {
    std::fprintf(stderr, "hmt-partition: error: %s\n", e.what());
    return static_cast<int>(e.code());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hmt-partition: internal error: %s\n", e.what());
    return static_cast<int>(hmt::ExitCode::kInternal);
  }
}

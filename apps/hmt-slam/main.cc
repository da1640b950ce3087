// hmt-slam: command-line front end. Argument parsing only; the work is done
// by the libraries.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "hmt/area/area_size.h"
#include "hmt/common/config.h"
#include "hmt/common/error.h"
#include "hmt/io/log_reader.h"
#include "hmt/io/rawlog.h"
#include "hmt/pipeline/hmt_job.h"
#include "hmt/pipeline/metric_job.h"
#include "hmt/topology/topology_file.h"

namespace {

// `hybrid`: the HMT-SLAM job (run, or resume when `resume_map` names a saved
// run's hmt_map.bin); otherwise the metric RBPF over the whole log as one map
// (metric), the global-RBPF baseline.
int run(const std::string& config_path, const std::string& input,
        const std::string& out_dir, const std::vector<std::string>& sets,
        bool quiet, bool hybrid, const std::string& resume_map = "") {
  hmt::Config cfg = hmt::Config::from_file(config_path);
  for (const auto& s : sets) cfg.apply_override(s);
  const std::string cfg_dir = std::filesystem::path(config_path).parent_path().string();
  hmt::pipeline::JobOptions opt = hmt::pipeline::load_job_options(cfg, cfg_dir);
  if (!input.empty()) opt.input.log = input;
  if (opt.input.log.empty())
    throw hmt::UsageError("no input log: give --input or set [input] log in " + config_path);
  std::fprintf(stderr, "hmt-slam: reading %s\n", opt.input.log.c_str());
  // Read before the log: a bad map file fails at once.
  std::unique_ptr<hmt::topology::Session> session;
  if (!resume_map.empty())
    session = std::make_unique<hmt::topology::Session>(hmt::topology::load_session(resume_map));
  const hmt::Log log = opt.input.select(hmt::io::read_log(opt.input.log, opt.input.bag));
  std::fprintf(stderr, "hmt-slam: %zu scans; %d particles\n", log.steps.size(),
               opt.rbpf.particles);
  if (hmt::area::resolve_tau(opt.area, log))
    std::fprintf(stderr, "hmt-slam: [area] tau = auto: %.3f from the laser's field of view\n",
                 opt.area.partition.tau);
  if (hybrid) {
    const auto sum = hmt::pipeline::run_hmt_job(opt, log, cfg, out_dir, !quiet, session.get());
    std::printf("processed %zu scans in %.2f s (peak memory %.1f MB)\n", sum.scans,
                sum.wall_time_s, sum.peak_rss_bytes / (1024.0 * 1024.0));
    std::printf("areas: %zu, arcs: %zu, loop closures accepted: %zu\n", sum.areas, sum.arcs,
                sum.loop_closures);
    std::printf("final pose (global): x=%.3f y=%.3f theta=%.4f\n", sum.final_pose.x,
                sum.final_pose.y, sum.final_pose.theta);
    if (!sum.map_png.empty()) std::printf("map image: %s\n", sum.map_png.c_str());
    std::printf("outputs in: %s\n", out_dir.c_str());
    return 0;
  }
  const auto sum = hmt::pipeline::run_metric_job(opt, log, cfg, out_dir, !quiet);
  std::printf("processed %zu scans in %.2f s (peak memory %.1f MB)\n", sum.scans,
              sum.wall_time_s, sum.peak_rss_bytes / (1024.0 * 1024.0));
  std::printf("final pose: x=%.3f y=%.3f theta=%.4f\n", sum.final_pose.x,
              sum.final_pose.y, sum.final_pose.theta);
  if (!sum.map_png.empty()) std::printf("map image: %s\n", sum.map_png.c_str());
  std::printf("outputs in: %s\n", out_dir.c_str());
  return 0;
}

int convert(const std::string& input, const std::string& output,
            const std::string& format, const std::vector<std::string>& sets) {
  hmt::io::RawlogFormat f;
  if (format == "sf")
    f = hmt::io::RawlogFormat::kActionsSensoryFrames;
  else if (format == "obs")
    f = hmt::io::RawlogFormat::kObservationsOnly;
  else
    throw hmt::UsageError("--format must be 'sf' or 'obs', not '" + format + "'");
  // A bag's topics and frames: the [input] keys, given with --set.
  hmt::Config cfg;
  for (const auto& s : sets) cfg.apply_override(s);
  hmt::io::BagOptions bag;
  bag.load(cfg, "input");
  cfg.check_all_used();
  const hmt::Log log = hmt::io::read_log(input, bag);
  hmt::io::write_rawlog(log, output, f);
  std::printf("wrote %zu scans to %s\n", log.steps.size(), output.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // A file-size limit (ulimit -f, or a quota) would otherwise kill the
  // process with SIGXFSZ in the middle of writing an output; ignored, the
  // write fails (EFBIG) and ends in the OutputError naming the file, and the
  // atomic writes leave no partial file.
  std::signal(SIGXFSZ, SIG_IGN);
  CLI::App app{"HMT-SLAM: hybrid metric-topological SLAM on 2D laser logs"};
  app.require_subcommand(1);

  std::string config, input, out = "out";
  std::vector<std::string> sets;
  bool quiet = false;
  auto* run_cmd = app.add_subcommand(
      "run", "HMT-SLAM on a whole log: global map, topology, trajectory, PMF");
  auto* metric_cmd = app.add_subcommand(
      "metric", "the metric RBPF alone over the whole log as one map (baseline)");
  std::string resume_map;
  auto* resume_cmd = app.add_subcommand(
      "resume", "continue a saved HMT-SLAM run (its hmt_map.bin) with more log");
  resume_cmd->add_option("--map,-m", resume_map, "hmt_map.bin written by run or resume")
      ->required();
  for (CLI::App* cmd : {run_cmd, metric_cmd, resume_cmd}) {
    cmd->add_option("--config,-c", config, "INI configuration file")->required();
    cmd->add_option("--input,-i", input, "log (.rawlog, .log, .log.gz, .bag); overrides [input] log");
    cmd->add_option("--out,-o", out, "output folder")->capture_default_str();
    cmd->add_option("--set", sets, "override a key: SECTION.key=value (repeatable)");
    cmd->add_flag("--quiet,-q", quiet, "no progress output");
  }

  std::string conv_in, conv_out, format = "sf";
  auto* conv_cmd = app.add_subcommand("convert", "convert a log (e.g. CARMEN) into an MRPT rawlog");
  conv_cmd->add_option("--input,-i", conv_in, "input log")->required();
  conv_cmd->add_option("--output,-o", conv_out, "output .rawlog")->required();
  conv_cmd->add_option("--format,-f", format,
                       "sf: Actions/SensoryFrame (what rbpf-slam reads); obs: observations only")
      ->capture_default_str();
  std::vector<std::string> conv_sets;
  conv_cmd->add_option("--set", conv_sets,
                       "a ROS bag's [input] key: input.scan_topic=/scan ... (repeatable)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : static_cast<int>(hmt::ExitCode::kUsage);
  }
  try {
    if (*run_cmd) return run(config, input, out, sets, quiet, true);
    if (*metric_cmd) return run(config, input, out, sets, quiet, false);
    if (*resume_cmd) return run(config, input, out, sets, quiet, true, resume_map);
    if (*conv_cmd) return convert(conv_in, conv_out, format, conv_sets);
  } catch (const hmt::Error& e) {
    std::fprintf(stderr, "hmt-slam: error: %s\n", e.what());
    return static_cast<int>(e.code());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hmt-slam: internal error: %s\n", e.what());
    return static_cast<int>(hmt::ExitCode::kInternal);
  }
  return 0;
}

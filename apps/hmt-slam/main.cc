// hmt-slam: command-line front end. Argument parsing only; the work is done
// by the libraries.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <memory>
#include <new>
#include <string>
#include <system_error>
#include <vector>

#include "hmt/checkpoint/checkpoint.h"
#include "hmt/common/config.h"
#include "hmt/common/error.h"
#include "hmt/common/files.h"
#include "hmt/common/resources.h"
#include "hmt/io/log_reader.h"
#include "hmt/io/log_stream.h"
#include "hmt/io/rawlog.h"
#include "hmt/islands/islands_job.h"
#include "hmt/pipeline/default_config.h"
#include "hmt/pipeline/hmt_job.h"
#include "hmt/pipeline/input_steps.h"
#include "hmt/pipeline/metric_job.h"
#include "hmt/pipeline/options_from_log.h"
#include "hmt/pipeline/stop_signal.h"
#include "hmt/topology/topology_file.h"
#include "hmt/version.h"

namespace {

// `hybrid`: the HMT-SLAM job (run, or resume when `resume_map` names a saved
// run's hmt_map.bin); otherwise the metric RBPF over the whole log as one map
// (metric), the global-RBPF baseline.
// With `checkpoint`: continue the interrupted run that wrote it, with its
// configuration (configs and sets must be empty), its log unless `input`
// names where the log is now, and its --report.
int run(const std::vector<std::string>& configs, const std::string& input,
        const std::string& out_dir, const std::vector<std::string>& sets,
        bool quiet, bool hybrid, bool report, const std::string& resume_map = "",
        const std::string& checkpoint = "") {
  // The built-in defaults (config/default.ini), each --config, then --set.
  hmt::Config cfg = hmt::pipeline::layered_config(configs, sets);
  std::string log_path = input;
  if (!checkpoint.empty()) {
    const hmt::checkpoint::RunIdentity id = hmt::checkpoint::read_identity(checkpoint);
    cfg = hmt::Config::from_string(id.config, checkpoint + " (the run's configuration)");
    report = id.report;
    std::fprintf(stderr, "hmt-slam: resuming after scan %llu from %s\n",
                 static_cast<unsigned long long>(id.steps), checkpoint.c_str());
    if (log_path.empty()) log_path = id.input;
  }
  hmt::pipeline::JobOptions opt = hmt::pipeline::load_job_options(cfg, "");
  if (!log_path.empty()) opt.input.log = log_path;
  opt.output.report = report;
  if (opt.input.log.empty())
    throw hmt::UsageError("no input log: give --input or set [input] log");
  std::fprintf(stderr, "hmt-slam: reading %s\n", opt.input.log.c_str());
  // Read before the log: a bad map file fails at once.
  std::unique_ptr<hmt::topology::Session> session;
  if (!resume_map.empty())
    session = std::make_unique<hmt::topology::Session>(hmt::topology::load_session(resume_map));
  // The log is read as the run goes (and, for run, again after it for the
  // keyframes' scans): memory does not grow with its length.
  const hmt::pipeline::LogOpener open = [&] {
    return hmt::io::open_log(opt.input.log, opt.input.bag);
  };
  hmt::pipeline::InputSteps steps(open(), opt.input);
  std::fprintf(stderr, "hmt-slam: %d particles\n", opt.rbpf.particles);
  // tau and the matching range follow from the log's first steps.
  hmt::pipeline::resolve_options_from_log(opt, steps);
  if (hybrid) {
    hmt::pipeline::install_stop_handlers();
    const auto sum = hmt::pipeline::run_hmt_job(opt, steps, open, cfg, out_dir, !quiet,
                                                session.get(), checkpoint);
    std::printf("processed %zu scans in %.2f s (peak memory %.1f MB)\n", sum.scans,
                sum.wall_time_s, sum.peak_rss_bytes / (1024.0 * 1024.0));
    std::printf("areas: %zu, arcs: %zu, loop closures accepted: %zu\n", sum.areas, sum.arcs,
                sum.loop_closures);
    std::printf("final pose (global): x=%.3f y=%.3f theta=%.4f\n", sum.final_pose.x,
                sum.final_pose.y, sum.final_pose.theta);
    if (!sum.map_png.empty()) std::printf("map image: %s\n", sum.map_png.c_str());
    if (!sum.report_html.empty()) std::printf("report: %s\n", sum.report_html.c_str());
    std::printf("outputs in: %s\n", out_dir.c_str());
    return 0;
  }
  const auto sum = hmt::pipeline::run_metric_job(opt, steps, cfg, out_dir, !quiet);
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
  // Streamed: each step is written as it is read, so a long log is never
  // held whole; a log that turns out damaged leaves no output behind.
  const auto log = hmt::io::open_log(input, bag);
  const size_t n = hmt::io::write_rawlog(*log, output, f);
  std::printf("wrote %zu scans to %s\n", n, output.c_str());
  return 0;
}

// R over a map and the islands chosen from it (hmt/islands/islands_job.h).
// The options are the configuration's [islands] keys, layered as for run
// (built-in defaults, each --config, --set; every key checked).
int islands(const std::string& map, const std::vector<std::string>& configs, std::string out_dir,
            const std::vector<std::string>& sets, bool check) {
  hmt::Config cfg = hmt::pipeline::layered_config(configs, sets);
  const hmt::pipeline::JobOptions opt = hmt::pipeline::load_job_options(cfg, "");
  if (out_dir.empty())
    out_dir = (std::filesystem::path(map).parent_path() / "islands").string();
  std::fprintf(stderr, "hmt-slam: distinctiveness of %s\n", map.c_str());
  const hmt::islands::CheckSetup setup{opt.islands_check, opt.rbpf.matcher, opt.rbpf.insertion};
  const auto sum = hmt::islands::run_islands_job(map, opt.islands, out_dir, check ? &setup : nullptr);
  hmt::write_text_atomically(out_dir + "/config_effective.ini", cfg.effective_ini());
  std::printf("%s\n", sum.map_description.c_str());
  std::printf("R over %zu free cells (%zu evaluated) in %.2f s; mean R %.3f\n", sum.free_cells,
              sum.evaluated_cells, sum.compute_time_s, sum.mean_r);
  std::printf("islands (R >= %.2f, >= %.1f m apart): %zu\n", opt.islands.threshold,
              opt.islands.min_distance, sum.islands.size());
  for (const auto& is : sum.islands)
    std::printf("  %d: x=%.2f y=%.2f R=%.3f\n", is.id, is.x, is.y, is.r);
  if (sum.checked)
    std::printf("localization check: %zu samples, Spearman rank correlation of R and the "
                "matcher's error %.3f (localization_check.csv)\n",
                sum.check.samples.size(), sum.check.spearman);
  std::printf("heat map: %s/distinctiveness.png\n", out_dir.c_str());
  std::printf("outputs in: %s\n", out_dir.c_str());
  return 0;
}

// `config --dump`: the built-in defaults as written in config/default.ini;
// with --config or --set, every value in force once they are layered on the
// defaults (checked as a run checks them).
int dump_config(const std::vector<std::string>& configs, const std::vector<std::string>& sets) {
  std::string text = hmt::pipeline::default_config_text();
  if (!configs.empty() || !sets.empty()) {
    hmt::Config cfg = hmt::pipeline::layered_config(configs, sets);
    hmt::pipeline::load_job_options(cfg, "");
    text = cfg.effective_ini();
  }
  if (std::fputs(text.c_str(), stdout) == EOF || std::fflush(stdout) != 0)
    throw hmt::OutputError("cannot write the configuration to standard output");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  hmt::tune_allocator();  // resources.h says why
  // A file-size limit (ulimit -f, or a quota) would otherwise kill the
  // process with SIGXFSZ in the middle of writing an output; ignored, the
  // write fails (EFBIG) and ends in the OutputError naming the file, and the
  // atomic writes leave no partial file.
  std::signal(SIGXFSZ, SIG_IGN);
  CLI::App app{"HMT-SLAM: hybrid metric-topological SLAM on 2D laser logs"};
  app.require_subcommand(1);
  app.set_version_flag("--version", hmt::version_string("hmt-slam"));

  std::vector<std::string> configs;
  std::string input, out = "out";
  std::vector<std::string> sets;
  bool quiet = false;
  bool report = false;
  auto* run_cmd = app.add_subcommand(
      "run", "HMT-SLAM on a whole log: global map, topology, trajectory, PMF");
  auto* metric_cmd = app.add_subcommand(
      "metric", "the metric RBPF alone over the whole log as one map (baseline)");
  std::string resume_map, checkpoint;
  auto* resume_cmd = app.add_subcommand(
      "resume",
      "continue an interrupted run from its checkpoint.bin, or a finished run (its "
      "hmt_map.bin) with more log");
  auto* map_opt =
      resume_cmd->add_option("--map,-m", resume_map, "hmt_map.bin written by run or resume");
  auto* ckpt_opt = resume_cmd->add_option(
      "--checkpoint", checkpoint,
      "checkpoint.bin of an interrupted run: continues it with its own configuration and log "
      "(--input if the log has moved); --out defaults to the checkpoint's folder");
  map_opt->excludes(ckpt_opt);
  for (CLI::App* cmd : {run_cmd, resume_cmd})
    cmd->add_flag("--report", report,
                  "also write OUT/report/index.html: a page to step through the run");
  for (CLI::App* cmd : {run_cmd, metric_cmd, resume_cmd}) {
    cmd->add_option("--config,-c", configs,
                    "INI file layered on the built-in defaults (config/default.ini); "
                    "repeatable, later files win");
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

  std::string isl_map, isl_out;
  std::vector<std::string> isl_configs;
  std::vector<std::string> isl_sets;
  bool isl_check = false;
  auto* isl_cmd = app.add_subcommand(
      "islands", "the distinctiveness measure R over a map and the islands of reliability");
  isl_cmd->add_option("--map,-m", isl_map,
                      "a run's hmt_map.bin, or a map_server map (.yaml, or .pgm beside it)")
      ->required();
  isl_cmd->add_option("--config,-c", isl_configs,
                      "INI file layered on the defaults (its [islands] keys; repeatable)");
  isl_cmd->add_option("--out,-o", isl_out, "output folder [the map's folder/islands]");
  isl_cmd->add_option("--set", isl_sets, "override a key: islands.key=value (repeatable)");
  isl_cmd->add_flag("--check", isl_check,
                    "also match simulated scans from offset poses: R against the error");
  bool dump = false;
  auto* config_cmd = app.add_subcommand("config", "print the configuration");
  config_cmd->add_flag("--dump", dump,
                       "the built-in defaults (config/default.ini); with --config or --set, "
                       "every value in force once they are layered on them")
      ->required();
  config_cmd->add_option("--config,-c", configs, "INI file layered on the defaults (repeatable)");
  config_cmd->add_option("--set", sets, "override a key: SECTION.key=value (repeatable)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : static_cast<int>(hmt::ExitCode::kUsage);
  }
  try {
    if (*run_cmd) return run(configs, input, out, sets, quiet, true, report);
    if (*metric_cmd) return run(configs, input, out, sets, quiet, false, false);
    if (*resume_cmd && !checkpoint.empty()) {
      if (!configs.empty() || !sets.empty())
        throw hmt::UsageError(
            "resume --checkpoint continues with the run's own configuration: no --config or "
            "--set");
      const std::string dir = std::filesystem::path(checkpoint).parent_path().string();
      return run({}, input, resume_cmd->count("--out") ? out : (dir.empty() ? "." : dir), {},
                 quiet, true, report, "", checkpoint);
    }
    if (*resume_cmd && resume_map.empty())
      throw hmt::UsageError("resume needs --checkpoint (an interrupted run) or --map (a finished one)");
    if (*resume_cmd) return run(configs, input, out, sets, quiet, true, report, resume_map);
    if (*conv_cmd) return convert(conv_in, conv_out, format, conv_sets);
    if (*config_cmd) return dump_config(configs, sets);
    if (*isl_cmd) return islands(isl_map, isl_configs, isl_out, isl_sets, isl_check);
  } catch (const hmt::Error& e) {
    // Stopped on request: not an error, though the exit code says the run
    // did not end.
    std::fprintf(stderr, "hmt-slam: %s%s\n", e.code() == hmt::ExitCode::kInterrupted ? "" : "error: ",
                 e.what());
    return static_cast<int>(e.code());
  } catch (const std::bad_alloc&) {
    // Memory exhaustion is not a bug, but nothing else can be done with it
    // either: say so plainly. Outputs are written to temporary files and
    // renamed, so what an earlier run left in the output folder is intact.
    std::fprintf(stderr,
                 "hmt-slam: internal error: out of memory: the run needed more memory than this "
                 "process may use (the machine's free memory, or a limit such as ulimit -v); "
                 "files already in the output folder were left as they were\n");
    return static_cast<int>(hmt::ExitCode::kInternal);
  } catch (const std::system_error& e) {
    // std::thread reports a thread it could not start (no memory for its
    // stack, or a process limit) as EAGAIN: name the cause, not the errno.
    const bool no_resources = e.code() == std::errc::resource_unavailable_try_again ||
                              e.code() == std::errc::not_enough_memory;
    std::fprintf(stderr, "hmt-slam: internal error: %s%s\n",
                 no_resources ? "out of memory or of threads (ulimit -v / -u): " : "", e.what());
    return static_cast<int>(hmt::ExitCode::kInternal);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hmt-slam: internal error: %s\n", e.what());
    return static_cast<int>(hmt::ExitCode::kInternal);
  }
  return 0;
}

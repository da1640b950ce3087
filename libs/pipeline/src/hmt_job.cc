#include "hmt/pipeline/hmt_job.h"

#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <thread>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "hmt/checkpoint/checkpoint.h"
#include "hmt/common/error.h"
#include "hmt/common/files.h"
#include "hmt/common/progress.h"
#include "hmt/common/resources.h"
#include "hmt/global_map/global_grid.h"
#include "hmt/global_map/global_poses.h"
#include "hmt/global_map/keyframe_graph.h"
#include "hmt/global_map/keyframe_map.h"
#include "hmt/global_map/overlay.h"
#include "hmt/grid/map_export.h"
#include "hmt/grid/png.h"
#include "hmt/framework/hmt_system.h"
#include "hmt/io/tum.h"
#include "hmt/pipeline/hmt_outputs.h"
#include "hmt/pipeline/metric_summary.h"
#include "hmt/pipeline/report.h"
#include "hmt/pipeline/rtl_probe.h"
#include "hmt/pipeline/stop_signal.h"
#include "hmt/topology/topology_file.h"
#include "kept_steps.h"
#include "mrpt_map_outputs.h"

namespace hmt::pipeline {
namespace {

constexpr double kMB = 1024.0 * 1024.0;

// One pose per log step from `first` on (`steps` of them) in the global
// frame: each area visit's poses composed with its area's global pose (a
// later visit overrides the step they share at the switch).
std::vector<Pose2D> global_trajectory(const std::vector<hybrid::TrajectorySegment>& segs,
                                      const global_map::GlobalPoses& poses, uint64_t first,
                                      size_t steps) {
  std::vector<Pose2D> out(steps);
  std::vector<char> set(steps, 0);
  for (const auto& s : segs) {
    auto it = poses.poses.find(s.area);
    if (it == poses.poses.end()) continue;
    for (size_t k = 0; k < s.poses.size(); ++k) {
      const uint64_t step = s.first_step + k;
      if (step < first || step - first >= steps) continue;
      out[step - first] = it->second.mean + s.poses[k];
      set[step - first] = 1;
    }
  }
  for (size_t i = 1; i < steps; ++i)
    if (!set[i]) out[i] = out[i - 1];
  return out;
}

nlohmann::json closure_json(const tlca::ClosureReport& c) {
  return {{"step", c.record.step},
          {"from", c.record.from},
          {"to", c.record.to},
          {"aligned", c.aligned},
          {"consistent", c.consistent},
          {"loop_hops", c.loop_hops},
          {"loop_chi2", c.loop_chi2},
          {"correction_m", c.correction_m},
          {"inlier_ratio", c.inlier_ratio},
          {"overlap_points", c.overlap_points},
          {"reason", c.reason}};
}

// What the filter did (summary.json), from a finished system.
nlohmann::json run_summary(const framework::HmtSystem& system) {
  const hybrid::HybridFilter& filter = system.filter();
  const auto& st = filter.stats();
  nlohmann::json j;
  j["keyframes"] = st.keyframes;
  j["new_area_events"] = st.new_area_events;
  j["transitions_evaluated"] = filter.transitions().size();
  j["loop_closures_accepted"] = st.loop_closures_accepted;
  // Every closure TLCA fused, in order: whether fine alignment refined it,
  // and whether it agreed with the grids and the map (tlca/acceptance.h;
  // an inconsistent one was fused with an inflated covariance).
  nlohmann::json closures = nlohmann::json::array();
  size_t inconsistent = 0;
  for (const hybrid::AcceptanceEvent& ev : filter.acceptances())
    for (const tlca::ClosureReport& c : ev.closures) {
      inconsistent += c.consistent ? 0 : 1;
      closures.push_back(closure_json(c));
    }
  j["loop_closures_inconsistent"] = inconsistent;
  j["loop_closures"] = closures;
  j["max_hypotheses_alive"] = st.max_hypotheses_alive;
  j["hypotheses_at_end"] = filter.hypotheses().size();
  // The hypothesis whose map the outputs draw (tsbi_events.csv's `child`
  // leads back from it through the decisions its map rests on).
  if (!filter.hypotheses().empty()) j["best_hypothesis"] = filter.best().id;
  j["metric_slam"] = metric_summary(filter.hypotheses().empty() ? metric_slam::RbpfStats{}
                                                              : filter.best().filter.stats());
  j["forgotten_path_entries"] = st.forgotten_path_entries;
  // Per-process totals (s): where the time went (the threads overlap).
  const auto& pt = system.times();
  auto total = [](const std::vector<double>& v) {
    double t = 0.0;
    for (double x : v) t += x;
    return t / 1000.0;
  };
  j["process_time_s"] = {{"metric_slam", total(pt.metric_slam)}, {"aam", total(pt.aam)},
                         {"tsbi", total(pt.tsbi)}, {"tlca", total(pt.tlca)}};
  return j;
}

}  // namespace

HmtJobSummary run_hmt_job(const JobOptions& opt, InputSteps& steps, const LogOpener& reopen,
                          const Config& cfg, const std::string& out_dir, bool show_progress,
                          const topology::Session* resume_from,
                          const std::string& checkpoint_path) {
  const auto t0 = std::chrono::steady_clock::now();
  if (opt.output.report && !opt.output.png)
    throw UsageError("--report draws over map.png, which [output] png = false turns off");
  make_directories(out_dir);
  // A run killed while writing leaves a temporary beside the output.
  remove_stale_temporaries(out_dir);
  // The configuration first: a run that fails later still says what it used.
  // The same text goes into every checkpoint.
  const std::string config_text = cfg.effective_ini();
  write_text_atomically(out_dir + "/config_effective.ini", config_text);

  const std::string& source = steps.source();
  if (!steps.peek()) throw InputError(source + ": the log has no scans");
  // The log is read as the run goes: of each step only its timestamp and
  // odometry are kept (the trajectory's clock; the keyframe graph's motion).
  KeptSteps kept;
  // Held by pointer: released (every particle's map) once its results are
  // out, before the global map is drawn, so the two never add up.
  hybrid::HmtOptions hmt_options = opt.hmt();
  hmt_options.hybrid.record_closure_views = opt.output.report;
  auto owned = std::make_unique<framework::HmtSystem>(hmt_options, opt.framework);
  framework::HmtSystem& system = *owned;
  const uint64_t first_step = resume_from ? resume_from->steps : 0;
  if (resume_from) system.resume(*resume_from);
  // An interrupted run: its state, and the log it was given checked step by
  // step against the fingerprint of the part it processed (those steps are
  // read, not fed).
  size_t start = 0;
  uint32_t log_crc = 0;
  LogStep step;
  if (!checkpoint_path.empty()) {
    // Loaded before the log is checked against it: the file is read once,
    // and a wrong log only costs the load on the way to its error.
    const checkpoint::RunIdentity id = checkpoint::load(checkpoint_path, system);
    const auto too_short = [&](size_t n) {
      return InputError("checkpoint '" + checkpoint_path + "' holds " + std::to_string(id.steps) +
                        " scans, but the log '" + source + "' has only " + std::to_string(n) +
                        ": not the log it was written from");
    };
    for (size_t i = 0; i < id.steps; ++i) {
      if (!steps.next(step)) throw too_short(i);
      log_crc = checkpoint::log_fingerprint(log_crc, step);
      kept.add(step);
    }
    if (!steps.peek()) throw too_short(static_cast<size_t>(id.steps));
    if (log_crc != id.log_crc)
      throw InputError("the log '" + source + "' does not begin with the " +
                       std::to_string(id.steps) + " scans checkpoint '" + checkpoint_path +
                       "' processed: not the log it was written from");
    start = static_cast<size_t>(id.steps);
  }
  const std::string checkpoint_out = out_dir + "/checkpoint.bin";
  const auto save_checkpoint = [&](size_t steps) {
    checkpoint::RunIdentity id;
    id.config = config_text;
    id.input = opt.input.log;
    id.steps = steps;
    id.log_crc = log_crc;
    id.report = opt.output.report;
    system.run_between_steps([&] { checkpoint::save(checkpoint_out, id, system); });
  };
  // A live run's processes are never all idle between two scans and its
  // results depend on timing: there is no state that would resume it.
  const bool live = opt.framework.mode == framework::Mode::kLive;
  const bool periodic = opt.output.checkpoint_every > 0 && !live;
  if (opt.output.checkpoint_every > 0 && !periodic)
    std::fprintf(stderr, "hmt-slam: [framework] mode = live: no checkpoints ([output] "
                 "checkpoint_every = %d ignored; a live run cannot be resumed)\n",
                 opt.output.checkpoint_every);
  // The total when the reader knows it (a log read whole), else progress by
  // the share of the file read.
  const std::optional<size_t> total = steps.total_steps();
  Progress progress("scans", total.value_or(0));
  progress.set_enabled(show_progress);
  system.start();
  std::unique_ptr<RtlProbe> probe;
  if (opt.framework.rtl_probe_hz > 0) probe = std::make_unique<RtlProbe>(system, opt.framework.rtl_probe_hz);
  // Live mode replays the log at its own pace (scaled), as the robot sensed it.
  const bool paced = opt.framework.mode == framework::Mode::kLive && opt.framework.live_speed > 0;
  const double first_timestamp = start > 0 ? kept.timestamps.front() : steps.peek()->timestamp;
  const auto replay_start = std::chrono::steady_clock::now();
  char extra[128];
  for (size_t i = start; steps.next(step); ++i) {
    if (paced)
      std::this_thread::sleep_until(
          replay_start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                             std::chrono::duration<double>((step.timestamp - first_timestamp) /
                                                           opt.framework.live_speed)));
    system.feed(step);
    kept.add(step);
    const framework::MetricEstimate e = system.metric_layer().estimate();
    const framework::TopologySummary topo = system.topological_layer().summary();
    std::snprintf(extra, sizeof extra, "areas %zu  hypotheses %zu  closures %zu  ESS %.0f",
                  topo.best_areas, topo.hypotheses.size(), topo.closures_accepted, e.ess);
    progress.set_fraction(steps.fraction_read());
    progress.update(e.valid && e.step >= first_step ? e.step + 1 - first_step : 0, extra);
    log_crc = checkpoint::log_fingerprint(log_crc, step);
    const int sig = stop_signal();
    if (sig != 0) {
      progress.finish();
      std::string where = "no checkpoint: a live run cannot be resumed";
      if (!live) {
        save_checkpoint(i + 1);
        where = "checkpoint written to " + checkpoint_out + "; continue with: hmt-slam resume "
                "--checkpoint " + checkpoint_out;
      }
      throw InterruptedError(std::string("stopped by ") + signal_name(sig) + " after scan " +
                             std::to_string(i + 1) +
                             (total ? " of " + std::to_string(*total) : std::string()) + "; " +
                             where);
    }
    // Not after the last scan: the outputs follow at once.
    if (periodic && (i + 1) % opt.output.checkpoint_every == 0 && steps.peek())
      save_checkpoint(i + 1);
  }
  const size_t n = steps.taken();
  system.finish();
  if (probe) probe->stop();
  // Metric SLAM may have been behind the feeding: every scan is done now.
  progress.update(n);
  progress.finish();
  const hybrid::HybridFilter& filter = system.filter();
  size_t peak_map_bytes = 0;
  for (const auto& t : system.traces()) peak_map_bytes = std::max(peak_map_bytes, t.map_memory_bytes);

  // What the processes did, and the state to resume from.
  topology::save_session(out_dir + "/hmt_map.bin", system.session());
  write_pmf_csv(out_dir + "/topological_pmf.csv", system.traces());
  write_ess_csv(out_dir + "/ess.csv", system.traces());
  write_memory_csv(out_dir + "/memory.csv", system.traces());
  write_process_times_csv(out_dir + "/process_times.csv", system.times(), system.traces());
  write_tsbi_events_csv(out_dir + "/tsbi_events.csv", filter.transitions());
  write_tsbi_candidates_csv(out_dir + "/tsbi_candidates.csv", filter.transitions());
  if (probe) write_rtl_csv(out_dir + "/rtl.csv", probe->samples());
  nlohmann::json j = run_summary(system);
  // The best hypothesis's filter, over the whole log (a hypothesis
  // carries its parent's counts).
  warn_if_scans_did_not_match(j["metric_slam"]);
  steps.warn_if_clock_faults();
  j["input"] = source;
  j["timestamps_not_increasing"] = steps.clock_faults().count;
  j["particles"] = opt.rbpf.particles;
  j["area_tau"] = opt.area.partition.tau;
  j["matching_range_m"] = opt.rbpf.matcher.max_range;
  j["peak_map_memory_mb"] = peak_map_bytes / kMB;
  j["framework_mode"] =
      opt.framework.mode == framework::Mode::kLive ? "live" : "deterministic";

  // The most probable hypothesis's map and path; then the particles go.
  std::vector<tlca::ClosureReport> at_end;
  const topology::HmtMap map = filter.final_map(&at_end);
  // The output hypothesis's closures the log ended too early to accept,
  // aligned for the output map (hybrid_filter.h).
  j["loop_closures_at_end"] = nlohmann::json::array();
  for (const tlca::ClosureReport& c : at_end) j["loop_closures_at_end"].push_back(closure_json(c));
  const std::vector<hybrid::TrajectorySegment> segments = filter.final_trajectory();
  // The report takes what it draws of the filter before the filter goes.
  std::unique_ptr<ReportWriter> report_writer;
  if (opt.output.report) {
    report_writer = std::make_unique<ReportWriter>(out_dir);
    report_writer->add_filter(system.traces(), filter.transitions(), filter.acceptances());
  }
  HmtJobSummary sum;
  sum.loop_closures = filter.stats().loop_closures_accepted;
  owned.reset();
  // The particles' maps and the other hypotheses just went: their pages go
  // back to the system before the global map's own allocations.
  release_free_memory();

  // Area poses by least squares over every arc (002 Sec. IV-C), the
  // shortest-path tree as the fallback when the optimisation cannot run:
  // the global map itself with [global_map] method = areas, the keyframe
  // graph's starting point otherwise.
  global_map::PoseGraphReport report;
  global_map::GlobalPoses poses;
  std::string pose_method = "least_squares";
  try {
    poses = global_map::optimize_poses(map, 1, {}, &report);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hmt-slam: warning: global optimisation failed (%s); "
                 "using the shortest-path tree\n", e.what());
    poses = global_map::shortest_path_poses(map, 1);
    pose_method = "shortest_path";
  }
  std::vector<global_map::AreaVisit> visits;
  for (const auto& s : segments) visits.push_back({s.area, s.first_step, s.poses, s.blind});
  // Of the steps, the graph reads only the keyframes' scans, and the MRPT
  // outputs those of their keyframes (the graph's, or visit_keyframes() if
  // the graph fails); which steps those are is known only now, from the
  // final path. So the log is read a second time for just those scans,
  // rather than holding every scan through the run. Any other step in the
  // range is served as its kept odometry without a scan.
  const auto in_range = [&](uint64_t s) { return s >= first_step && s - first_step < n; };
  std::set<uint64_t> wanted;
  if (opt.global_map.method == global_map::GlobalMapMethod::kKeyframes) {
    const LogStep present;
    const global_map::StepSource held = [&](uint64_t s) { return in_range(s) ? &present : nullptr; };
    for (uint64_t s : global_map::keyframe_steps(visits, held, opt.global_map.graph))
      wanted.insert(s);
  }
  if (opt.output.mrpt_maps)
    for (const global_map::KeyframeNode& k : visit_keyframes(visits, poses, opt.global_map.graph))
      wanted.insert(k.step);
  const std::map<uint64_t, LogStep> scans =
      wanted.empty() ? std::map<uint64_t, LogStep>()
                     : read_steps_again(reopen, opt.input, first_step, n, log_crc, wanted);
  const global_map::StepSource step_at = [&](uint64_t s) -> const LogStep* {
    if (!in_range(s)) return nullptr;
    const auto it = scans.find(s);
    if (it != scans.end()) return &it->second;
    // Valid until the next call on this thread: the graph reads a step's
    // odometry as soon as it asks for it.
    thread_local LogStep bare;
    bare = kept.bare_step(static_cast<size_t>(s - first_step));
    return &bare;
  };

  std::vector<Pose2D> traj;
  std::vector<global_map::KeyframeNode> keyframes;  // what the map was drawn from
  grid::OccupancyGrid global(opt.rbpf.resolution);
  nlohmann::json graph_json;
  bool placed = false;
  if (opt.global_map.method == global_map::GlobalMapMethod::kKeyframes) {
    // The keyframe graph: the trajectory placed keyframe by keyframe and the
    // map drawn from the keyframes' scans; the area-grain map if it fails.
    try {
      const auto tg = std::chrono::steady_clock::now();
      const global_map::KeyframeGraph graph = global_map::optimize_keyframe_graph(
          map, visits, step_at, poses, opt.global_map.graph, opt.rbpf.matcher, opt.rbpf.threads,
          report.outliers);
      traj = global_map::keyframe_trajectory(visits, graph.nodes, first_step, n);
      global = global_map::render_keyframe_grid(graph.nodes, step_at, opt.rbpf.resolution,
                                                opt.rbpf.insertion);
      poses = graph.areas;
      if (opt.output.mrpt_maps) keyframes = graph.nodes;
      const global_map::KeyframeGraphReport& r = graph.report;
      graph_json = {{"area_nodes", r.area_nodes},
                    {"keyframe_nodes", r.keyframe_nodes},
                    {"constraints", {{"in_area", r.in_area},
                                     {"consecutive", r.consecutive},
                                     {"arcs", r.arcs},
                                     {"matches", r.matches}}},
                    {"matches_tried", r.matches_tried},
                    {"matches_reused", r.matches_reused},
                    {"down_weighted", r.down_weighted},
                    {"rounds", r.rounds},
                    {"converged", r.converged},
                    {"last_round_move_m", r.last_round_move_xy},
                    {"last_round_move_rad", r.last_round_move_theta},
                    {"iterations", r.iterations},
                    {"initial_cost", r.initial_cost},
                    {"final_cost", r.final_cost},
                    {"solve_time_s", r.time_s},
                    {"time_s", std::chrono::duration<double>(
                                   std::chrono::steady_clock::now() - tg).count()}};
      placed = true;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "hmt-slam: warning: keyframe graph failed (%s); "
                   "placing whole areas\n", e.what());
    }
  }
  if (!placed) {
    traj = global_trajectory(segments, poses, first_step, n);
    global = global_map::render_global_grid(map, poses, opt.rbpf.resolution);
    if (opt.output.mrpt_maps) keyframes = visit_keyframes(visits, poses, opt.global_map.graph);
  }
  std::vector<io::StampedPose> stamped;
  for (size_t i = 0; i < n; ++i) stamped.push_back({kept.timestamps[i], traj[i]});

  sum.scans = n;
  sum.final_pose = traj.back();
  sum.areas = map.area_count();
  sum.arcs = map.arcs().size();
  io::write_tum(out_dir + "/trajectory.tum", stamped);

  // The images are rendered band by band as they are written: a large map
  // is never held whole as a picture (grid/row_source.h).
  const grid::MapFrame frame = grid::map_frame(global, opt.output.map_margin);
  if (opt.output.png) {
    sum.map_png = out_dir + "/map.png";
    grid::MapRows grey(global, frame);
    grid::write_png_file(grey, sum.map_png);
    global_map::TopologyOverlayRows overlay(global, frame, map, poses);
    grid::write_png_file(overlay, out_dir + "/map_topology.png");
    make_directories(out_dir + "/areas");
    for (topology::AreaId id : map.area_ids())
      if (const auto& m = map.area(id).map)
        grid::write_png(grid::render(*m, opt.output.map_margin),
                        out_dir + "/areas/area_" + std::to_string(id) + ".png");
  }
  if (opt.output.pgm) {
    grid::MapRows grey(global, frame);
    grid::write_pgm_yaml(grey, frame, out_dir + "/map");
  }
  if (opt.output.mrpt_maps)
    write_mrpt_map_outputs(global, frame, keyframes, poses, opt.global_map.graph, step_at,
                           out_dir);
  write_topology_json(out_dir + "/topology.json", map, poses);
  write_topology_dot(out_dir + "/topology.dot", map);

  sum.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  sum.peak_rss_bytes = peak_rss_bytes();
  j["scans"] = sum.scans;
  j["wall_time_s"] = sum.wall_time_s;
  j["peak_rss_mb"] = sum.peak_rss_bytes / kMB;
  j["final_pose"] = {{"x", sum.final_pose.x}, {"y", sum.final_pose.y},
                     {"theta", sum.final_pose.theta}};
  j["areas"] = sum.areas;
  j["arcs"] = sum.arcs;
  // The loop arcs the robust estimate switched off (false loop closures,
  // global_poses.h): listed, so a map drawn without them says so.
  nlohmann::json outliers = nlohmann::json::array();
  for (const global_map::OutlierArc& o : report.outliers)
    outliers.push_back({{"from", o.from}, {"to", o.to}, {"chi2", o.chi2}});
  j["global_poses"] = {{"method", pose_method},
                       {"iterations", report.iterations},
                       {"initial_chi2", report.initial_chi2},
                       {"final_chi2", report.final_chi2},
                       {"converged", report.converged},
                       {"tested_arcs", report.tested_arcs},
                       {"max_arc_chi2", report.max_arc_chi2},
                       {"outlier_arcs", outliers}};
  j["global_map"] = {{"method", placed ? "keyframes" : "areas"}};
  if (placed) j["global_map"]["keyframe_graph"] = graph_json;
  write_text_atomically(out_dir + "/summary.json", j.dump(2) + "\n");
  // Every output is in place: the run needs no resuming.
  std::error_code ec;
  std::filesystem::remove(checkpoint_out, ec);
  if (report_writer) {
    report_writer->add_map(frame, traj, first_step, segments, map, poses);
    sum.report_html = report_writer->write(j.dump());
  }
  return sum;
}

}  // namespace hmt::pipeline

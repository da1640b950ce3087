// hmt-experiments: the experiments of the area-abstraction paper (000 Sec. 6).
//   info-loss      information loss of map partitions in EKF landmark SLAM
//                  (Eq. 22, Fig. 8): runs, summary, one run's map
//   field-of-view  number of areas for sensors of different fields of view
// Argument parsing and output only; the work is done by hmt_experiments.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "hmt/area/area_options.h"
#include "hmt/common/error.h"
#include "hmt/common/files.h"
#include "hmt/common/progress.h"
#include "hmt/experiments/fov_experiment.h"
#include "hmt/experiments/info_loss.h"
#include "hmt/version.h"

namespace {

using namespace hmt::experiments;
using hmt::Point2D;
using hmt::Pose2D;
using json = nlohmann::json;
constexpr double kDeg = M_PI / 180.0;

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

json stats_json(const Stats& s) {
  return {{"n", s.n},         {"mean", s.mean}, {"std", s.std},
          {"p16", s.p16},     {"median", s.median}, {"p84", s.p84},
          {"min", s.min},     {"max", s.max}};
}

double mean_of(const std::vector<int>& v) {
  double s = 0.0;
  for (int x : v) s += x;
  return v.empty() ? 0.0 : s / v.size();
}

int info_loss(const InfoLossOptions& o, const std::string& out, bool quiet) {
  o.validate();
  hmt::make_directories(out);
  const auto t0 = std::chrono::steady_clock::now();
  hmt::Progress progress("runs", o.runs);
  progress.set_enabled(!quiet);
  const auto runs = run_info_loss(o, [&](int done) { progress.update(done); });
  const double wall = seconds_since(t0);
  progress.finish();

  // Per-run values, long format.
  std::ostringstream csv;
  csv.precision(10);
  csv << "run,method,param,groups,e\n";
  for (const RunResult& r : runs) {
    csv << r.run << ",spectral_main," << o.tau << "," << r.groups_spectral << ","
        << r.e_spectral << "\n";
    csv << r.run << ",even_same_count," << o.tau << "," << r.groups_spectral << ","
        << r.e_even << "\n";
    for (size_t i = 0; i < o.taus.size(); ++i)
      csv << r.run << ",spectral," << o.taus[i] << "," << r.groups_tau[i] << ","
          << r.e_tau[i] << "\n";
    for (size_t i = 0; i < r.e_fixed.size(); ++i)
      csv << r.run << ",fixed," << o.k_min + static_cast<int>(i) << ","
          << r.groups_fixed[i] << "," << r.e_fixed[i] << "\n";
  }
  hmt::write_text_atomically(out + "/info_loss_runs.csv", csv.str());

  // Summary: one row per method and parameter.
  struct Row {
    std::string method;
    double param;
    Stats e;
    double groups;
  };
  std::vector<Row> rows;
  auto collect = [&](const std::string& method, double param, auto e_of, auto g_of) {
    std::vector<double> e;
    std::vector<int> g;
    for (const RunResult& r : runs) {
      e.push_back(e_of(r));
      g.push_back(g_of(r));
    }
    rows.push_back({method, param, summarize(e), mean_of(g)});
  };
  collect("spectral_main", o.tau, [](const RunResult& r) { return r.e_spectral; },
          [](const RunResult& r) { return r.groups_spectral; });
  collect("even_same_count", o.tau, [](const RunResult& r) { return r.e_even; },
          [](const RunResult& r) { return r.groups_spectral; });
  for (size_t i = 0; i < o.taus.size(); ++i)
    collect("spectral", o.taus[i], [i](const RunResult& r) { return r.e_tau[i]; },
            [i](const RunResult& r) { return r.groups_tau[i]; });
  for (int k = o.k_min; k <= o.k_max; ++k) {
    const size_t i = static_cast<size_t>(k - o.k_min);
    collect("fixed", k, [i](const RunResult& r) { return r.e_fixed[i]; },
            [i](const RunResult& r) { return r.groups_fixed[i]; });
  }
  std::ostringstream sum;
  sum.precision(10);
  sum << "method,param,runs,mean_groups,e_mean,e_std,e_p16,e_median,e_p84,e_min,e_max\n";
  for (const Row& r : rows)
    sum << r.method << "," << r.param << "," << r.e.n << "," << r.groups << ","
        << r.e.mean << "," << r.e.std << "," << r.e.p16 << "," << r.e.median << ","
        << r.e.p84 << "," << r.e.min << "," << r.e.max << "\n";
  hmt::write_text_atomically(out + "/info_loss_summary.csv", sum.str());

  // One run in full, for the map plot (Fig. 8a).
  RunDetail d;
  run_info_loss_once(o, 0, &d);
  json ex;
  for (const Point2D& p : d.sim.landmarks) ex["landmarks_true"].push_back({p.x, p.y});
  for (size_t k = 0; k < d.map_ids.size(); ++k)
    ex["map"].push_back({{"id", d.map_ids[k]},
                         {"mean", {d.map_means[k].x(), d.map_means[k].y()}},
                         {"cov", {d.map_covs[k](0, 0), d.map_covs[k](0, 1), d.map_covs[k](1, 1)}}});
  for (size_t t = 0; t < d.sim.steps.size(); ++t) {
    const SimStep& s = d.sim.steps[t];
    json ids = json::array();
    for (const RangeBearing& m : s.z) ids.push_back(m.id);
    ex["steps"].push_back({{"true_pose", {s.true_pose.x, s.true_pose.y, s.true_pose.theta}},
                           {"pose", {d.poses[t].mean.x, d.poses[t].mean.y, d.poses[t].mean.theta}},
                           {"group", d.spectral_labels[t]},
                           {"ids", ids}});
  }
  ex["tau"] = o.tau;
  hmt::write_text_atomically(out + "/info_loss_example.json", ex.dump() + "\n");

  json meta;
  meta["experiment"] = "information loss (000 Sec. 6.1, Eq. 22, Fig. 8)";
  meta["options"] = {{"runs", o.runs},
                     {"seed", o.seed},
                     {"threads", o.threads},
                     {"tau", o.tau},
                     {"taus", o.taus},
                     {"k_min", o.k_min},
                     {"k_max", o.k_max},
                     {"information", to_string(o.form)},
                     {"sso_with_ids", o.use_ids},
                     {"sso_gate", o.sso.gate},
                     {"min_sso", o.min_sso},
                     {"split_method", hmt::area::to_string(o.split_method)},
                     {"landmarks", o.sim.landmarks},
                     {"path_length_m", o.sim.path_length},
                     {"step_m", o.sim.step},
                     {"observations", o.sim.steps() + 1},
                     {"landmark_x", {o.sim.x_min, o.sim.x_max}},
                     {"landmark_half_width_m", o.sim.half_width},
                     {"max_range_m", o.sim.max_range},
                     {"fov_deg", o.sim.fov / kDeg},
                     {"range_std_m", o.sim.range_std},
                     {"bearing_std_deg", o.sim.bearing_std / kDeg},
                     {"odo_xy_std_m", o.sim.odo_xy_std},
                     {"odo_phi_std_deg", o.sim.odo_phi_std / kDeg}};
  for (const Row& r : rows)
    meta["summary"].push_back({{"method", r.method},
                               {"param", r.param},
                               {"mean_groups", r.groups},
                               {"e", stats_json(r.e)}});
  meta["wall_time_s"] = wall;
  hmt::write_text_atomically(out + "/info_loss.json", meta.dump(2) + "\n");

  // The table.
  auto pct = [](double v) { return fmt("%7.3f", 100.0 * v); };
  std::printf("Information loss e (Eq. 22) over %d runs, %d observations each; "
              "e in %%, 68%% interval = [p16, p84]\n",
              o.runs, o.sim.steps() + 1);
  std::printf("%-10s %6s %8s %8s %8s %8s %8s %8s\n", "method", "param", "groups",
              "mean", "std", "p16", "median", "p84");
  for (const Row& r : rows) {
    if (r.method == "spectral") continue;
    const std::string name = r.method == "fixed"           ? "fixed k"
                             : r.method == "even_same_count" ? "even"
                                                             : "spectral";
    std::printf("%-10s %6s %8.2f %s %s %s %s %s\n", name.c_str(),
                fmt(r.method == "fixed" ? "%.0f" : "t=%.2f", r.param).c_str(), r.groups,
                pct(r.e.mean).c_str(), pct(r.e.std).c_str(), pct(r.e.p16).c_str(),
                pct(r.e.median).c_str(), pct(r.e.p84).c_str());
  }
  std::printf("groups: sub-maps (groups that sensed a landmark), mean over runs; even: as "
              "many equal consecutive groups as the spectral partition's sub-maps\n");
  std::printf("\ne against tau (spectral partition):\n");
  std::printf("%6s %8s %8s %8s %8s %8s %8s\n", "tau", "groups", "mean", "std", "p16",
              "median", "p84");
  for (const Row& r : rows) {
    if (r.method != "spectral") continue;
    std::printf("%6.3g %8.2f %s %s %s %s %s\n", r.param, r.groups, pct(r.e.mean).c_str(),
                pct(r.e.std).c_str(), pct(r.e.p16).c_str(), pct(r.e.median).c_str(),
                pct(r.e.p84).c_str());
  }
  std::printf("\n%d runs in %.1f s on %d threads (%.3f thread-seconds per run); outputs in %s\n",
              o.runs, wall, o.threads, wall * o.threads / o.runs, out.c_str());
  return 0;
}

int field_of_view(const FovOptions& o, const std::string& world_name, double max_range,
                  const std::string& out) {
  o.validate();
  World world;
  std::vector<Point2D> route;
  if (world_name == "building") {
    world = building();
    route = building_route();
  } else if (world_name == "two-rooms") {
    world = two_rooms();
    route = two_rooms_route();
  } else {
    throw hmt::UsageError("--world must be 'building' or 'two-rooms', not '" +
                          world_name + "'");
  }
  hmt::make_directories(out);
  const auto poses = route_poses(route, o.step, o.turn_step);
  const auto t0 = std::chrono::steady_clock::now();
  const auto results = run_field_of_view(world, poses, standard_sensors(max_range), o);
  const double wall = seconds_since(t0);

  std::ostringstream csv;
  csv.precision(10);
  csv << "sensor,fov_deg,beams,max_range,tau,keyframes,edges,mean_degree,areas,seconds\n";
  for (const FovResult& r : results)
    csv << r.sensor << "," << r.fov_deg << "," << r.beams << "," << r.max_range << ","
        << r.tau << "," << r.keyframes << "," << r.edges << "," << r.mean_degree << ","
        << r.areas << "," << r.seconds << "\n";
  hmt::write_text_atomically(out + "/field_of_view.csv", csv.str());

  json j;
  j["experiment"] = "field of view (000 Sec. 6.2)";
  j["world"] = world_name;
  j["options"] = {{"step_m", o.step},
                  {"turn_step_deg", o.turn_step / kDeg},
                  {"delta_m", o.area.sso.delta},
                  {"min_sso", o.area.min_sso},
                  {"split_method", hmt::area::to_string(o.area.partition.split_method)},
                  {"taus", o.taus},
                  {"max_range_m", max_range}};
  for (const Segment& s : world.walls) j["walls"].push_back({s.x0, s.y0, s.x1, s.y1});
  for (const Pose2D& p : poses) j["poses"].push_back({p.x, p.y, p.theta});
  for (const FovResult& r : results)
    j["results"].push_back({{"sensor", r.sensor},
                            {"fov_deg", r.fov_deg},
                            {"beams", r.beams},
                            {"tau", r.tau},
                            {"keyframes", r.keyframes},
                            {"edges", r.edges},
                            {"mean_degree", r.mean_degree},
                            {"areas", r.areas},
                            {"labels", r.labels},
                            {"seconds", r.seconds}});
  j["wall_time_s"] = wall;
  hmt::write_text_atomically(out + "/field_of_view.json", j.dump() + "\n");

  std::printf("Field of view: %zu keyframes along the route of '%s' (every %.2f m, "
              "every %.0f deg turning), range %.0f m\n",
              poses.size(), world_name.c_str(), o.step, o.turn_step / kDeg, max_range);
  std::printf("%-8s %7s %6s %5s %7s %11s %6s %8s\n", "sensor", "fov_deg", "beams", "tau",
              "edges", "mean_degree", "areas", "time_s");
  for (const FovResult& r : results)
    std::printf("%-8s %7.0f %6d %5.2f %7ld %11.2f %6d %8.2f\n", r.sensor.c_str(),
                r.fov_deg, r.beams, r.tau, r.edges, r.mean_degree, r.areas, r.seconds);
  std::printf("\n%.1f s; outputs in %s\n", wall, out.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"HMT-SLAM experiments: the area-abstraction paper's Sec. 6"};
  app.require_subcommand(1);
  app.set_version_flag("--version", hmt::version_string("hmt-experiments"));

  InfoLossOptions il;
  std::string il_out = "/tmp/hmt-experiments", information = "joint", split = "mean";
  double fov_deg = il.sim.fov / kDeg, bearing_deg = il.sim.bearing_std / kDeg,
         odo_phi_deg = il.sim.odo_phi_std / kDeg;
  bool no_ids = false, quiet = false;
  auto* il_cmd = app.add_subcommand(
      "info-loss", "information loss e (Eq. 22) of the spectral partition vs fixed k (Fig. 8)");
  il_cmd->add_option("--runs,-n", il.runs, "simulation runs")->capture_default_str();
  il_cmd->add_option("--seed", il.seed, "seed of run 0 (run r has its own stream)")
      ->capture_default_str();
  il_cmd->add_option("--threads,-j", il.threads, "worker threads")->capture_default_str();
  il_cmd->add_option("--out,-o", il_out, "output folder")->capture_default_str();
  il_cmd->add_option("--tau", il.tau, "threshold of the spectral partition of Fig. 8(b)")
      ->capture_default_str();
  il_cmd->add_option("--taus", il.taus, "thresholds of Fig. 8(c)")
      ->delimiter(',')
      ->capture_default_str();
  il_cmd->add_option("--k-min", il.k_min, "smallest fixed group size")->capture_default_str();
  il_cmd->add_option("--k-max", il.k_max, "largest fixed group size")->capture_default_str();
  il_cmd->add_option("--information", information,
                     "joint: landmark blocks of the inverse joint covariance (the "
                     "authors' implementation); marginal: inverse of the map's covariance")
      ->capture_default_str();
  il_cmd->add_flag("--no-ids", no_ids,
                   "SSO by the Mahalanobis test alone (landmark ids not used as descriptors)");
  il_cmd->add_option("--split-method", split, "mean, sign or sweep")->capture_default_str();
  il_cmd->add_option("--landmarks", il.sim.landmarks, "landmarks per run")->capture_default_str();
  il_cmd->add_option("--path-length", il.sim.path_length, "straight path [m]")
      ->capture_default_str();
  il_cmd->add_option("--step", il.sim.step, "distance between observations [m]")
      ->capture_default_str();
  il_cmd->add_option("--half-width", il.sim.half_width,
                     "landmarks within this distance of the path's line [m]")
      ->capture_default_str();
  il_cmd->add_option("--max-range", il.sim.max_range, "sensor range [m]")->capture_default_str();
  il_cmd->add_option("--fov-deg", fov_deg, "sensor field of view [deg]")->capture_default_str();
  il_cmd->add_option("--range-std", il.sim.range_std, "range noise [m]")->capture_default_str();
  il_cmd->add_option("--bearing-std-deg", bearing_deg, "bearing noise [deg]")
      ->capture_default_str();
  il_cmd->add_option("--odo-xy-std", il.sim.odo_xy_std, "odometry noise per step [m]")
      ->capture_default_str();
  il_cmd->add_option("--odo-phi-std-deg", odo_phi_deg, "odometry heading noise per step [deg]")
      ->capture_default_str();
  il_cmd->add_flag("--quiet,-q", quiet, "no progress output");

  FovOptions fo;
  std::string fo_out = "/tmp/hmt-experiments", world = "building", fo_split = "mean";
  double max_range = 20.0, turn_deg = fo.turn_step / kDeg;
  auto* fo_cmd = app.add_subcommand(
      "field-of-view", "number of areas for 360, 180 and 65 degree sensors (Sec. 6.2)");
  fo_cmd->add_option("--out,-o", fo_out, "output folder")->capture_default_str();
  fo_cmd->add_option("--world", world, "building or two-rooms")->capture_default_str();
  fo_cmd->add_option("--taus", fo.taus, "partition thresholds")
      ->delimiter(',')
      ->capture_default_str();
  fo_cmd->add_option("--step", fo.step, "keyframe every this many metres")
      ->capture_default_str();
  fo_cmd->add_option("--turn-deg", turn_deg, "keyframe every this many degrees turning")
      ->capture_default_str();
  fo_cmd->add_option("--max-range", max_range, "range of all three sensors [m]")
      ->capture_default_str();
  fo_cmd->add_option("--delta", fo.area.sso.delta, "SSO point-match distance [m]")
      ->capture_default_str();
  fo_cmd->add_option("--split-method", fo_split, "mean, sign or sweep")->capture_default_str();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : static_cast<int>(hmt::ExitCode::kUsage);
  }
  try {
    if (*il_cmd) {
      il.sim.fov = fov_deg * kDeg;
      il.sim.bearing_std = bearing_deg * kDeg;
      il.sim.odo_phi_std = odo_phi_deg * kDeg;
      il.sim.x_max = il.sim.x_min + il.sim.path_length;
      il.use_ids = !no_ids;
      try {
        il.split_method = hmt::area::parse_split_method(split, "info-loss", "--split-method");
        il.form = parse_information_form(information);
        il.validate();
      } catch (const std::invalid_argument& e) {
        throw hmt::UsageError(e.what());
      } catch (const hmt::ConfigError& e) {
        throw hmt::UsageError(e.what());
      }
      return info_loss(il, il_out, quiet);
    }
    if (*fo_cmd) {
      fo.turn_step = turn_deg * kDeg;
      try {
        fo.area.partition.split_method =
            hmt::area::parse_split_method(fo_split, "field-of-view", "--split-method");
        fo.validate();
      } catch (const std::invalid_argument& e) {
        throw hmt::UsageError(e.what());
      } catch (const hmt::ConfigError& e) {
        throw hmt::UsageError(e.what());
      }
      return field_of_view(fo, world, max_range, fo_out);
    }
  } catch (const hmt::Error& e) {
    std::fprintf(stderr, "hmt-experiments: error: %s\n", e.what());
    return static_cast<int>(e.code());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hmt-experiments: internal error: %s\n", e.what());
    return static_cast<int>(hmt::ExitCode::kInternal);
  }
  return 0;
}

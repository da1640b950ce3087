#include "hmt/grouping/partition_job.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>

#include "hmt/area/area_size.h"
#include "hmt/area/offline_grouping.h"
#include "hmt/area/partition.h"
#include "hmt/area/scan_sso.h"
#include "hmt/area/spectral_bisection.h"
#include "hmt/common/error.h"
#include "hmt/common/files.h"
#include "hmt/common/progress.h"
#include "hmt/common/resources.h"
#include "hmt/grid/map_export.h"
#include "hmt/grid/scan_insertion.h"
#include "hmt/grouping/images.h"
#include "hmt/io/log_reader.h"
#include "hmt/metric_slam/matching_range.h"

namespace hmt::grouping {
namespace {

using Clock = std::chrono::steady_clock;
using nlohmann::json;

double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

json pose_json(const Pose2D& p) {
  return {{"x", p.x}, {"y", p.y}, {"theta", p.theta}};
}

std::string group_file(int g, const char* ext) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "group_%03d%s", g, ext);
  return buf;
}

// The group's Ncut against the rest, and its own best bisection's.
void group_ncuts(const area::WeightMatrix& W, const area::AreaOptions& o,
                 GroupInfo* gi) {
  const int n = static_cast<int>(W.rows());
  std::vector<char> in(static_cast<size_t>(n), 0);
  for (int k : gi->keyframes) in[static_cast<size_t>(k)] = 1;
  gi->ncut_vs_rest = static_cast<int>(gi->keyframes.size()) < n
                         ? area::normalized_cut(W, in)
                         : 0.0;
  if (gi->keyframes.size() >= 2) {
    const area::BisectionOptions bo{o.partition.split_method,
                                    o.partition.min_cluster_size};
    const area::Bisection b =
        area::spectral_bisection(area::submatrix(W, gi->keyframes), bo);
    gi->split_ncut = b.valid ? b.ncut : -1.0;
  }
}

// Valid returns of a scan within `max_range`, in the frame of `pose`'s parent.
std::vector<Point2D> end_points(const LaserScan& scan, const Pose2D& pose,
                                double max_range) {
  std::vector<Point2D> out;
  for (size_t i = 0; i < scan.size(); ++i) {
    if (!area::is_valid_return(scan, i) || scan.ranges[i] > max_range) continue;
    const double r = scan.ranges[i], a = scan.bearing(i);
    const Point2D s = scan.sensor_pose.transform({r * std::cos(a), r * std::sin(a)});
    out.push_back(pose.transform(s));
  }
  return out;
}

}  // namespace

GroupedLog group_log(const Log& log, ScanPoses poses,
                     const PartitionJobOptions& opt) {
  GroupedLog g;
  g.scans = poses.size();
  g.poses = std::move(poses);

  auto t = Clock::now();
  g.selection = select_keyframes(log, g.poses, opt.grouping.keyframe_distance,
                                 opt.grouping.keyframe_angle);
  const std::vector<area::Keyframe> kfs = area_keyframes(log, g.keyframes());
  g.time.keyframes_s = since(t);
  const int n = static_cast<int>(kfs.size());
  if (n < 2)
    throw InputError("'" + log.source + "' gives " + std::to_string(n) +
                     " keyframe(s) (scans with a pose and at least " +
                     std::to_string(kMinKeyframeReturns) +
                     " valid returns, spaced by the keyframe distance or "
                     "angle): at least 2 are needed to group");

  t = Clock::now();
  g.W = area::sso_weight_matrix(kfs, opt.area);
  g.time.sso_matrix_s = since(t);

  t = Clock::now();
  const area::PartitionResult part =
      area::recursive_partition(g.W, opt.area.partition);
  g.time.partition_s = since(t);
  g.accepted_ncuts = part.accepted_ncuts;
  g.label = area::group_labels(part.groups, n);
  for (const std::vector<int>& members : part.groups) {
    GroupInfo gi;
    gi.keyframes = members;
    for (int k : members) {
      if (!gi.runs.empty() && gi.runs.back().second == k - 1)
        gi.runs.back().second = k;
      else
        gi.runs.emplace_back(k, k);
    }
    group_ncuts(g.W, opt.area, &gi);
    g.groups.push_back(std::move(gi));
  }

  t = Clock::now();
  LocalMapOptions lo = opt.local_maps;
  lo.refine = opt.grouping.refine_local_maps;
  g.local = build_local_maps(log, g.keyframes(), part.groups, g.W, lo);
  g.time.local_maps_s = since(t);

  t = Clock::now();
  std::vector<Pose2D> global;
  global.reserve(g.keyframes().size());
  for (const KeyframeRecord& k : g.keyframes()) global.push_back(k.pose);
  g.arcs = build_topology(global, g.local.local_pose, g.label, g.W);
  g.time.topology_s = since(t);
  return g;
}

double write_partition_outputs(const Log& log, const GroupedLog& g,
                               const PartitionJobOptions& opt,
                               const std::string& out_dir, bool show_progress) {
  const auto t0 = Clock::now();
  make_directories(out_dir);
  const auto& kfs = g.keyframes();
  const int n = static_cast<int>(kfs.size());

  // Local maps.
  std::vector<TopologyNode> nodes;
  for (size_t gi = 0; gi < g.groups.size(); ++gi) {
    const int id = static_cast<int>(gi);
    const grid::MapImage img = grid::render(g.local.grids[gi], opt.map_margin);
    grid::write_png(img, out_dir + "/" + group_file(id, ".png"));
    if (opt.write_pgm) grid::write_pgm_yaml(img, out_dir + "/" + group_file(id, ""));
    TopologyNode node;
    node.id = id;
    node.keyframes = g.groups[gi].keyframes.size();
    node.reference_keyframe = g.groups[gi].keyframes.front();
    node.reference_pose = kfs[static_cast<size_t>(node.reference_keyframe)].pose;
    node.local_map = group_file(id, ".png");
    nodes.push_back(node);
  }

  // groups.json
  json j;
  j["input"] = log.source;
  j["poses"] = g.poses.source;
  j["options"] = {{"keyframe_distance", opt.grouping.keyframe_distance},
                  {"keyframe_angle", opt.grouping.keyframe_angle},
                  {"refine_local_maps", opt.grouping.refine_local_maps},
                  {"delta", opt.area.sso.delta},
                  {"use_probabilistic", opt.area.sso.use_probabilistic},
                  {"min_sso", opt.area.min_sso},
                  {"tau", opt.area.partition.tau},
                  {"min_cluster_size", opt.area.partition.min_cluster_size},
                  {"split_method", area::to_string(opt.area.partition.split_method)}};
  json jk = json::array();
  for (int k = 0; k < n; ++k) {
    const KeyframeRecord& r = kfs[static_cast<size_t>(k)];
    jk.push_back({{"id", k},
                  {"scan", r.scan},
                  {"timestamp", r.timestamp},
                  {"pose", pose_json(r.pose)},
                  {"group", g.label[static_cast<size_t>(k)]},
                  {"local_pose", pose_json(g.local.local_pose[static_cast<size_t>(k)])}});
  }
  j["keyframes"] = std::move(jk);
  json jg = json::array();
  for (size_t gi = 0; gi < g.groups.size(); ++gi) {
    const GroupInfo& info = g.groups[gi];
    json scans = json::array(), runs = json::array();
    for (int k : info.keyframes) scans.push_back(kfs[static_cast<size_t>(k)].scan);
    for (const auto& [a, b] : info.runs) runs.push_back({a, b});
    jg.push_back({{"id", gi},
                  {"keyframes", info.keyframes},
                  {"scans", std::move(scans)},
                  {"runs", std::move(runs)},
                  {"reference_keyframe", info.keyframes.front()},
                  {"reference_pose", pose_json(nodes[gi].reference_pose)},
                  {"ncut_vs_rest", info.ncut_vs_rest},
                  {"split_ncut", info.split_ncut >= 0.0 ? json(info.split_ncut) : json()},
                  {"local_map", nodes[gi].local_map}});
  }
  j["groups"] = std::move(jg);
  j["labels"] = g.label;
  j["accepted_ncuts"] = g.accepted_ncuts;
  write_text_atomically(out_dir + "/groups.json", j.dump(2) + "\n");

  // Weight matrix before and after reordering by group.
  std::vector<int> time_order(static_cast<size_t>(n)), group_order, sizes;
  for (int k = 0; k < n; ++k) time_order[static_cast<size_t>(k)] = k;
  for (const GroupInfo& info : g.groups) {
    group_order.insert(group_order.end(), info.keyframes.begin(), info.keyframes.end());
    sizes.push_back(static_cast<int>(info.keyframes.size()));
  }
  grid::MapImage wimg;
  wimg.image = weight_image(g.W, time_order, {});
  grid::write_png(wimg, out_dir + "/weights.png");
  wimg.image = weight_image(g.W, group_order, sizes);
  grid::write_png(wimg, out_dir + "/weights_reordered.png");

  // Global map at the input poses, coarser if the area is very large.
  MapOverlay ov;
  ov.groups = static_cast<int>(g.groups.size());
  double x0 = std::numeric_limits<double>::max(), y0 = x0;
  double x1 = std::numeric_limits<double>::lowest(), y1 = x1;
  const double max_r = opt.local_maps.insertion.max_range;
  for (int k = 0; k < n; ++k) {
    const KeyframeRecord& r = kfs[static_cast<size_t>(k)];
    ov.pose.push_back(r.pose);
    ov.group.push_back(g.label[static_cast<size_t>(k)]);
    ov.points.push_back(end_points(log.steps[static_cast<size_t>(r.scan)].scan, r.pose, max_r));
    for (const Point2D& p : ov.points.back())
      x0 = std::min(x0, p.x), y0 = std::min(y0, p.y), x1 = std::max(x1, p.x),
      y1 = std::max(y1, p.y);
  }
  constexpr double kMaxMapSide = 4000.0;  // pixels
  double res = opt.local_maps.resolution;
  if (x1 > x0) res = std::max(res, std::max(x1 - x0, y1 - y0) / kMaxMapSide);
  grid::OccupancyGrid global(res);
  Progress progress("scans", g.scans);
  progress.set_enabled(show_progress);
  for (size_t i = 0; i < g.scans; ++i) {
    if (g.poses.has_pose[i])
      grid::insert_scan(global, g.poses.pose[i], log.steps[i].scan,
                        opt.local_maps.insertion);
    if ((i + 1) % 50 == 0 || i + 1 == g.scans) progress.update(i + 1, "global map");
  }
  progress.finish("global map");
  const grid::MapImage gimg = grid::render(global, opt.map_margin);
  grid::MapImage overlay = gimg;
  overlay.image = groups_map_image(gimg, ov);
  grid::write_png(overlay, out_dir + "/groups_map.png");

  // Topology.
  json jt;
  json jn = json::array(), ja = json::array();
  for (const TopologyNode& node : nodes)
    jn.push_back({{"id", node.id},
                  {"keyframes", node.keyframes},
                  {"reference_keyframe", node.reference_keyframe},
                  {"reference_scan", kfs[static_cast<size_t>(node.reference_keyframe)].scan},
                  {"reference_pose", pose_json(node.reference_pose)},
                  {"local_map", node.local_map}});
  for (const TopologyArc& a : g.arcs) {
    json cov;
    if (a.transform.has_cov) {
      cov = json::array();
      for (int r = 0; r < 3; ++r)
        cov.push_back({a.transform.cov(r, 0), a.transform.cov(r, 1), a.transform.cov(r, 2)});
    }
    ja.push_back({{"from", a.from},
                  {"to", a.to},
                  {"mean", pose_json(a.transform.mean)},
                  {"covariance", cov},
                  {"samples", a.transform.n},
                  {"route_pairs", a.route_pairs},
                  {"overlap_pairs", a.overlap_pairs},
                  {"sso_cut", a.sso_cut}});
  }
  jt["frame"] = "an arc's mean is the pose of group `to`'s reference frame "
                "in group `from`'s; a group's frame is its first keyframe's pose";
  jt["nodes"] = std::move(jn);
  jt["arcs"] = std::move(ja);
  write_text_atomically(out_dir + "/topology.json", jt.dump(2) + "\n");
  write_text_atomically(out_dir + "/topology.dot", topology_dot(nodes, g.arcs));
  return since(t0);
}

PartitionSummary run_partition(const PartitionJobOptions& options,
                               const PartitionRequest& req) {
  const auto t0 = Clock::now();
  PartitionJobOptions opt = options;
  make_directories(req.out_dir);
  write_text_atomically(req.out_dir + "/config_effective.ini", req.effective_config);

  auto t = Clock::now();
  const Log log = io::read_log(req.log_path, req.bag);
  area::resolve_tau(opt.area, log);  // tau = auto: from the sensor's field of view
  // max_range = auto: from the log's ranges.
  metric_slam::RangeSample ranges;
  for (size_t i = 0; i < log.steps.size() && !ranges.complete(); ++i)
    ranges.add(log.steps[i].scan, log.steps[i].odometry_increment);
  metric_slam::resolve_matching_range(opt.local_maps.matcher, opt.local_maps.insertion, ranges);
  const double read_s = since(t);
  t = Clock::now();
  ScanPoses poses =
      req.poses_path.empty()
          ? odometry_poses(log, opt.max_steps)
          : match_poses(log, read_pose_file(req.poses_path),
                        opt.grouping.pose_time_tolerance, req.poses_path,
                        opt.max_steps);
  const double poses_s = since(t);
  if (req.show_progress)
    std::fprintf(stderr, "hmt-partition: %zu scans, %zu with a pose (%s)\n",
                 poses.size(), poses.size() - poses.missing, poses.source.c_str());

  const GroupedLog g = group_log(log, std::move(poses), opt);
  if (req.show_progress)
    std::fprintf(stderr,
                 "hmt-partition: %zu keyframes, %zu SSO edges, %zu groups "
                 "(grouping %.3f s)\n",
                 g.keyframes().size(), static_cast<size_t>(g.W.nonZeros() / 2),
                 g.groups.size(), g.time.grouping_s());
  const double write_s = write_partition_outputs(log, g, opt, req.out_dir, req.show_progress);

  PartitionSummary s;
  s.scans = g.scans;
  s.keyframes = g.keyframes().size();
  s.groups = g.groups.size();
  s.arcs = g.arcs.size();
  s.grouping_s = g.time.grouping_s();
  s.total_s = since(t0);
  s.summary_path = req.out_dir + "/summary.json";

  json j;
  j["input"] = log.source;
  j["poses"] = g.poses.source;
  j["scans"] = g.scans;
  j["scans_with_pose"] = g.scans - g.poses.missing;
  j["scans_without_pose"] = g.poses.missing;
  j["keyframes"] = s.keyframes;
  j["scans_skipped_too_few_returns"] = g.selection.too_few_returns;
  j["sso_edges"] = static_cast<size_t>(g.W.nonZeros() / 2);
  j["groups"] = s.groups;
  j["arcs"] = s.arcs;
  j["local_map_matches"] = g.local.matched;
  j["local_map_rejected_matches"] = g.local.unmatched;
  j["time_s"] = {{"read_log", read_s},
                 {"poses", poses_s},
                 {"keyframes", g.time.keyframes_s},
                 {"sso_matrix", g.time.sso_matrix_s},
                 {"partition", g.time.partition_s},
                 {"grouping", g.time.grouping_s()},
                 {"local_maps", g.time.local_maps_s},
                 {"topology", g.time.topology_s},
                 {"outputs", write_s},
                 {"total", s.total_s}};
  j["grouping_s_per_100_keyframes"] =
      s.keyframes ? 100.0 * s.grouping_s / static_cast<double>(s.keyframes) : 0.0;
  j["grouping_s_per_100_scans"] =
      s.scans ? 100.0 * s.grouping_s / static_cast<double>(s.scans) : 0.0;
  j["peak_rss_mb"] = static_cast<double>(peak_rss_bytes()) / (1024.0 * 1024.0);
  write_text_atomically(s.summary_path, j.dump(2) + "\n");
  return s;
}

}  // namespace hmt::grouping

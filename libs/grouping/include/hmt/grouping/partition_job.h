// The offline grouping tool of 001 Sec. IV as one job (hmt-partition):
//  1. keyframes from the log and its poses (odometry or a trajectory file);
//  2. the SSO weight matrix W of the keyframes (001 Eq. 16-18);
//  3. the recursive min-Ncut partition into groups, and one local map per
//     group in the group's own frame (local_maps.h);
//  4. the metric-topological map: groups joined by averaged relative
//     transforms (topology.h);
// and the files that show it (see write_partition_outputs).
#pragma once

#include <string>
#include <vector>

#include "hmt/area/area_options.h"
#include "hmt/area/ncut.h"
#include "hmt/common/sensor_data.h"
#include "hmt/grouping/grouping_options.h"
#include "hmt/grouping/keyframes.h"
#include "hmt/grouping/local_maps.h"
#include "hmt/grouping/scan_poses.h"
#include "hmt/grouping/topology.h"
#include "hmt/io/rosbag.h"

namespace hmt::grouping {

struct PartitionJobOptions {
  GroupingOptions grouping;
  area::AreaOptions area;
  // Grid and scan matcher of the local maps; `refine` is overwritten by
  // grouping.refine_local_maps.
  LocalMapOptions local_maps;
  int map_margin = 10;     // [output] map_margin: cells around map images
  bool write_pgm = true;   // [output] pgm: local maps also as PGM + YAML
  size_t max_steps = 0;    // [input] max_steps: first N scans (0 = all)
};

struct GroupTimings {
  double keyframes_s = 0.0;
  double sso_matrix_s = 0.0;  // step 2
  double partition_s = 0.0;   // step 3, the recursive Ncut
  double local_maps_s = 0.0;  // step 3, the maps
  double topology_s = 0.0;    // step 4
  double grouping_s() const { return sso_matrix_s + partition_s; }
};

struct GroupInfo {
  std::vector<int> keyframes;            // ascending keyframe ids
  std::vector<std::pair<int, int>> runs; // maximal runs [first, last] of
                                         // consecutive keyframe ids
  double ncut_vs_rest = 0.0;  // Ncut(group, all other keyframes); 0 alone
  double split_ncut = -1.0;   // Ncut of the group's own best bisection (why
                              // it was not split); < 0 for one keyframe
};

struct GroupedLog {
  size_t scans = 0;  // scans considered
  ScanPoses poses;
  KeyframeSelection selection;
  area::WeightMatrix W;          // over the keyframes
  std::vector<GroupInfo> groups;  // ordered by their first keyframe
  std::vector<int> label;        // group of each keyframe
  std::vector<double> accepted_ncuts;
  LocalMaps local;
  std::vector<TopologyArc> arcs;
  GroupTimings time;

  const std::vector<KeyframeRecord>& keyframes() const {
    return selection.keyframes;
  }
};

// Steps 1-4 on the first opt.max_steps scans of `log` at `poses`. Throws
// hmt::InputError when fewer than 2 keyframes are found.
GroupedLog group_log(const Log& log, ScanPoses poses,
                     const PartitionJobOptions& opt);

// Writes into out_dir (created if needed; every file atomically):
//  groups.json        keyframes (scan, timestamp, pose, local pose, group),
//                     groups (keyframes, scans, runs, reference frame, Ncuts),
//                     the accepted Ncuts and the options that shaped them
//  group_NNN.png      each group's local map (+ .pgm/.yaml with write_pgm)
//  weights.png        W in log order; weights_reordered.png by group
//  groups_map.png     the global map (input poses) with the groups in colour
//  topology.json/.dot the metric-topological map
// Returns the seconds spent. Throws hmt::OutputError.
double write_partition_outputs(const Log& log, const GroupedLog& g,
                               const PartitionJobOptions& opt,
                               const std::string& out_dir, bool show_progress);

struct PartitionRequest {
  std::string log_path;
  io::BagOptions bag;            // which topics and frames of a ROS bag
  std::string poses_path;        // empty: odometry
  std::string out_dir;
  std::string effective_config;  // written as config_effective.ini
  bool show_progress = true;
};

struct PartitionSummary {
  size_t scans = 0, keyframes = 0, groups = 0, arcs = 0;
  double grouping_s = 0.0, total_s = 0.0;
  std::string summary_path;
};

// Reads the log and the poses, runs group_log and write_partition_outputs,
// then writes summary.json (counts and timings). config_effective.ini is
// written first, so a run that fails later still says what it used.
PartitionSummary run_partition(const PartitionJobOptions& opt,
                               const PartitionRequest& request);

}  // namespace hmt::grouping

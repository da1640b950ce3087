// A globally consistent map at keyframe grain: a sparse pose graph in the
// style of Cartographer's global optimisation, the HMT map's areas playing
// the role of its submaps.
//
// Why: optimize_poses() places whole areas, so the trajectory and the map
// are rigid blocks; an error inside an area, or in one arc, shows as a
// misplaced block and as a jump of the trajectory at every area switch.
// Here the robot's path itself is in the graph, and every place where two
// areas overlap is tied by scan matching, not only by the arcs.
//
// Nodes: every area's frame (its global pose) and a keyframe node every
// keyframe_distance / keyframe_angle of motion along the final path (plus
// one at the start of every area visit, so every step of a visit has a node
// of that visit to be placed from). Constraints, all relative poses
// "to seen from from" with residual difference(x_from^-1 x_to, mean) as in
// optimize_poses():
//   (a) in-area: area -> keyframe, the keyframe's pose in its area's frame
//       from the metric filter; std growing with the distance from the
//       area's origin (KeyframeGraphOptions).
//   (b) consecutive: keyframe -> next keyframe, their relative motion along
//       the path; across an area switch the switching step is known in both
//       areas' frames (the visits share it), so no arc is needed. Std
//       odometry-like, per metre and per radian.
//   (c) arcs: area -> area, the HMT map's arcs with their Gaussians.
//   (d) matches: area -> keyframe, the keyframe's scan matched
//       (metric_slam::ScanMatcher) in the grid of every other area whose
//       bounding box in the global frame holds the keyframe at the current
//       estimate; kept only if it explains a large fraction of the points
//       and stays within a gate of the estimate. Information: the matcher's
//       Gauss-Newton Hessian divided by an inflation for the correlated
//       beams, plus a floor covariance. A keyframe whose start in an area
//       moved less than the matcher's finest step since the last round
//       keeps that round's match there (match_reuse).
//       In the last round the keyframe's own area's grid is matched too
//       (match_own_area): (a) is the filter's pose against the area's map
//       as it was then, the grid holds the whole run's scans of the area.
// (c) and (d) go through a robust kernel (Huber or DCS), so a wrong arc or
// match is down-weighted instead of bending the map. The cost is minimised
// by iteratively reweighted Gauss-Newton with step halving, the normal
// equations solved by SuiteSparse CHOLMOD (as optimize_poses), the root
// area fixed as the gauge. A few rounds of (match, solve): each round
// matches again from the improved estimate, so overlaps that the area-grain
// estimate placed too far apart to match are found once they come closer.
//
// Deterministic: nodes, constraints and areas are in fixed orders (path
// order, ascending ids); the matching runs in parallel over keyframes, each
// writing its own slot, joined in keyframe order.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <vector>

#include "hmt/common/pose2d.h"
#include "hmt/common/sensor_data.h"
#include "hmt/global_map/global_map_options.h"
#include "hmt/global_map/global_poses.h"
#include "hmt/metric_slam/scan_matcher.h"
#include "hmt/topology/hmt_map.h"

namespace hmt::global_map {

// One visit of the robot to an area: its pose in the area's frame at every
// log step from first_step on. Consecutive visits share the switching step
// (the last pose of one and the first of the next are the same instant, in
// the two areas' frames).
struct AreaVisit {
  AreaId area = topology::kNoArea;
  uint64_t first_step = 0;
  std::vector<Pose2D> poses;
  // Per pose, the error that steps moved by the odometry alone (scans too
  // poor to weigh particles by) have added since the visit began
  // (metric_slam::GridRbpf::blind_trace()); empty when there is none. Where
  // it is not zero the pose is no better known in the area's frame than
  // that: its keyframe's tie to the area is widened by it, and it is not
  // matched in its own area's grid (drawn at those very poses), so that the
  // keyframes on either side of the stretch bend it through the odometry's
  // motion between them instead of the area holding it as dead-reckoned.
  std::vector<Eigen::Matrix3d> blind;
};

// The log step `step` (odometry and scan), or nullptr if the log used does
// not hold it (steps before a resumed run, past max_steps).
using StepSource = std::function<const LogStep*(uint64_t step)>;

struct KeyframeNode {
  AreaId area = topology::kNoArea;
  size_t visit = 0;   // index into the visits
  uint64_t step = 0;  // log step
  Pose2D in_area;     // pose in its area's frame (the metric filter's)
  Pose2D global;      // pose in the root's frame (the optimised one)
};

struct KeyframeGraphReport {
  size_t area_nodes = 0;
  size_t keyframe_nodes = 0;
  // Constraints of each kind in the last round.
  size_t in_area = 0;
  size_t consecutive = 0;
  size_t arcs = 0;
  size_t matches = 0;
  // Matches tried in the last round (kept + rejected by ratio or gate), and
  // how many of them reused an earlier round's match (match_reuse).
  size_t matches_tried = 0;
  size_t matches_reused = 0;
  // Robust constraints beyond the kernel's threshold at the final estimate.
  size_t down_weighted = 0;
  int rounds = 0;
  // Whether the last round moved no keyframe by more than round_tolerance
  // (the rounds ended early); false when they ran out first. The largest
  // move of a keyframe in the last round (m, rad) says by how much the
  // estimate was still changing when they stopped.
  bool converged = false;
  double last_round_move_xy = 0;
  double last_round_move_theta = 0;
  int iterations = 0;       // Gauss-Newton steps, all rounds
  double initial_cost = 0;  // robust cost of the first round at its start
  double final_cost = 0;    // at the end of the last round
  double time_s = 0;
};

struct KeyframeGraph {
  GlobalPoses areas;  // optimised area frames, marginal covariances
  std::vector<KeyframeNode> nodes;  // path order
  KeyframeGraphReport report;
};

// Builds and solves the graph. `initial` gives the areas' starting poses
// and the root (e.g. optimize_poses()); areas it lacks are placed from the
// path. `matcher` is the project's scan matcher configuration (its grids
// are the areas' archived maps). The scans are matched on `threads` threads
// (0: one per core; the result is the same for any count). Throws std::invalid_argument for an
// unknown root, visits of unknown areas or no keyframe at all, and
// std::runtime_error if the normal equations cannot be factorised. Arcs in
// `excluded` (the loop closures optimize_poses() switched off as gross
// errors) are left out of (c).
KeyframeGraph optimize_keyframe_graph(const topology::HmtMap& map,
                                      const std::vector<AreaVisit>& visits,
                                      const StepSource& steps,
                                      const GlobalPoses& initial,
                                      const KeyframeGraphOptions& options,
                                      const metric_slam::MatcherOptions& matcher,
                                      int threads = 1,
                                      const std::vector<OutlierArc>& excluded = {});

// The steps optimize_keyframe_graph() takes keyframes at, in path order:
// the only steps whose scans it reads (of the others it uses the odometry
// at most). Only whether `steps` holds a step matters here, not what it
// holds, so a caller can find which scans to load before loading them.
std::vector<uint64_t> keyframe_steps(const std::vector<AreaVisit>& visits,
                                     const StepSource& steps,
                                     const KeyframeGraphOptions& options);

}  // namespace hmt::global_map

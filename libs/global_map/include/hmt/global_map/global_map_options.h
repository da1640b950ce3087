// Options of the global map, INI section [global_map]: which estimate places
// the map in one frame, and the weights of the keyframe pose graph
// (keyframe_graph.h) that is the default one.
//
// The standard deviations below are the model of what each constraint is
// worth; they are documented with their defaults in config/default.ini.
#pragma once

#include <string>

#include "hmt/common/config.h"

namespace hmt::global_map {

enum class GlobalMapMethod {
  // A pose graph of area frames and keyframes (keyframe_graph.h): the
  // trajectory and the map are placed keyframe by keyframe.
  kKeyframes,
  // Whole areas placed by least squares over the arcs (optimize_poses), the
  // areas' grids pasted at their poses.
  kAreas,
};

enum class RobustKernel { kHuber, kDcs };

struct KeyframeGraphOptions {
  // A keyframe node every this much motion along the path (m, rad). Not
  // read from [global_map]: the pipeline copies [hmt] keyframe_distance /
  // keyframe_angle, the grain the area abstraction already works at.
  double keyframe_distance = 0.5;
  double keyframe_angle = 0.5;

  // (a) A keyframe's pose in its own area's frame, as the metric filter
  // estimated it: std = constant + part per metre from the area's origin
  // (the filter's drift inside an area grows with the distance travelled in
  // it, which the distance from the origin stands for).
  double in_area_std_xy = 0.02;               // [m]
  double in_area_std_xy_per_metre = 0.03;     // [m/m]
  double in_area_std_theta = 0.005;           // [rad]
  double in_area_std_theta_per_metre = 0.005; // [rad/m]

  // (b) Consecutive keyframes: their relative motion along the path, with
  // an odometry-like std growing with the distance and rotation between.
  double step_std_xy = 0.01;                 // [m]
  double step_std_xy_per_metre = 0.05;       // [m/m]
  double step_std_theta = 0.005;             // [rad]
  double step_std_theta_per_metre = 0.01;    // [rad/m]
  double step_std_theta_per_radian = 0.05;   // [rad/rad]

  // (d) A keyframe's scan matched in another area's grid.
  bool match = true;
  // ... and in its own area's grid. (a) is the metric filter's pose: a
  // draw from the particle's proposal, against the area's map as it was at
  // that step. The area's grid holds all of the area's scans of the run,
  // and matched in it a keyframe is placed against what the later scans
  // drew too (on aces at seed 1, 1.6 cm from (a) in the median, 8 cm at
  // the 90th percentile). Like a submap's own nodes in Cartographer's pose
  // graph, the area's keyframes then hold the area's shape more firmly
  // than (a) alone, whose spread grows with the distance from the origin.
  // So these matches join only in the last round (or in the round after
  // the estimate settled): a refinement once the loops are closed.
  bool match_own_area = true;
  // Kept only if the match explains at least this fraction of the scan's
  // points ...
  double match_min_ratio = 0.5;
  // ... and moved the pose by at most this much from the current estimate.
  double match_gate_xy = 0.5;     // [m]
  double match_gate_theta = 0.2;  // [rad]
  // The matcher's Gauss-Newton information assumes independent beams; the
  // beams of one scan are strongly correlated, so it is divided by this.
  double match_inflation = 50.0;
  // Added to the match covariance: a match is never better than the grids
  // it is made in.
  double match_std_xy = 0.02;      // [m]
  double match_std_theta = 0.005;  // [rad]
  // In the rounds after the first, a keyframe whose start in an area moved
  // by less than the matcher's finest hill-climbing step (both in x, y and
  // in heading) since it was last matched there keeps that match (its gate
  // checked again from the new start): to the matcher the two starts are
  // the same start, and matching again would only add its half-cell jitter.
  bool match_reuse = true;

  // Robust kernel on (c) arcs and (d) matches: Huber or dynamic covariance
  // scaling, with its threshold in squared Mahalanobis distance.
  RobustKernel kernel = RobustKernel::kDcs;
  double robust_chi2 = 9.0;

  // At most this many rounds of (match, solve); matching in each round
  // starts from the estimate the previous round left, so overlaps the
  // area-grain estimate placed too far apart are found as it improves.
  // The rounds end early once a round moved no keyframe by more than
  // round_tolerance (metres, and radians for the heading); with
  // match_own_area, after one more round that adds the own areas'
  // matches.
  int rounds = 5;
  double round_tolerance = 0.01;
  // Gauss-Newton iterations per round, and the relative cost decrease that
  // stops them.
  int max_iterations = 20;
  double relative_tolerance = 1e-6;

  // Reads every key above but the keyframe spacing from `section`.
  void load(Config& cfg, const std::string& section = "global_map");
};

struct GlobalMapOptions {
  GlobalMapMethod method = GlobalMapMethod::kKeyframes;
  KeyframeGraphOptions graph;
  void load(Config& cfg, const std::string& section = "global_map");
};

}  // namespace hmt::global_map

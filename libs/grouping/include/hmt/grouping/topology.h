// Step 4 of 001 Sec. IV: the metric-topological map. Nodes are the groups
// (each with its local map and reference frame, see local_maps.h); an arc
// joins two groups that are consecutive along the route (keyframes k and k+1
// in different groups) or whose keyframes sense common space (a non-zero SSO
// between a keyframe of each). Its value is the pose of the second group's
// reference frame in the first's, averaged over those keyframe pairs
// ("averaging the differential poses between scans of different groups"):
// pair (i in g, j in h) gives
//     T_ij = local_i (+) (global_j (-) global_i) (+) inverse(local_j)
// the relative pose of the pair from the input poses, carried into the two
// local frames. Without local refinement every pair gives the same T; with it,
// their spread (the sample covariance) says how well the two local maps agree
// with the input poses about where the groups lie.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "hmt/area/ncut.h"
#include "hmt/common/pose2d.h"

namespace hmt::grouping {

struct PoseSample {
  Pose2D mean;  // x, y averaged; theta the circular mean
  // Sample covariance of (x, y, theta) (n - 1 denominator, angles taken
  // relative to the mean); zero and `has_cov` false for fewer than 2.
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  bool has_cov = false;
  size_t n = 0;
};

// Throws std::invalid_argument for an empty list.
PoseSample average_poses(const std::vector<Pose2D>& samples);

struct TopologyArc {
  int from = 0, to = 0;  // group ids, from < to
  // The pose of `to`'s reference frame in `from`'s frame.
  PoseSample transform;
  size_t route_pairs = 0;    // consecutive keyframes across the two groups
  size_t overlap_pairs = 0;  // keyframe pairs with SSO > 0 (a pair can be both)
  double sso_cut = 0.0;      // sum of the SSO between the two groups
};

// `label[k]` is keyframe k's group; `global` / `local` its input pose and its
// pose in its group's frame; W the SSO matrix over the keyframes. Arcs sorted
// by (from, to).
std::vector<TopologyArc> build_topology(const std::vector<Pose2D>& global,
                                        const std::vector<Pose2D>& local,
                                        const std::vector<int>& label,
                                        const area::WeightMatrix& W);

struct TopologyNode {
  int id = 0;
  size_t keyframes = 0;
  int reference_keyframe = 0;
  Pose2D reference_pose;  // input frame
  std::string local_map;  // image file name
};

// Graphviz: a digraph whose edges point from `from` to `to` and read "pose
// of `to` in `from`'s frame"; nodes carry pos="x,y" (the reference position
// in metres times 72 points per metre, for `neato -n`).
std::string topology_dot(const std::vector<TopologyNode>& nodes,
                         const std::vector<TopologyArc>& arcs);

}  // namespace hmt::grouping

// Step 3 of 001 Sec. IV: one metric map per group, in the group's own frame.
//
// A group's reference frame is the pose of its first keyframe (in log
// order). Its keyframes are taken in log order; each starts at the pose the
// input poses give relative to an anchor, an earlier keyframe of the same
// group: local_anchor (+) (global_k (-) global_anchor). The anchor is the one
// with the largest SSO with k (ties: the latest), else the previous one:
// where the input poses make the two scans agree best, their relative pose is
// the most trustworthy — this matters when a group is revisited, as the
// previous keyframe of the group may then be far back along a drifting
// route. When refinement is on, the keyframe is then registered against the
// group's map built so far with the metric layer's scan matcher (hill
// climbing then Gauss-Newton on the likelihood field), and inserted. A match that finds obstacles for fewer than
// min_match_ratio of the beams is not trusted: the keyframe keeps its
// starting pose (counted in `unmatched`). Without refinement the local poses
// are exactly global_k (-) reference.
#pragma once

#include <vector>

#include "hmt/area/ncut.h"
#include "hmt/common/sensor_data.h"
#include "hmt/grid/occupancy_grid.h"
#include "hmt/grid/scan_insertion.h"
#include "hmt/grouping/keyframes.h"
#include "hmt/metric_slam/scan_matcher.h"

namespace hmt::grouping {

struct LocalMapOptions {
  double resolution = 0.05;  // [grid] resolution
  grid::InsertionOptions insertion;
  metric_slam::MatcherOptions matcher;
  bool refine = true;
};

struct LocalMaps {
  std::vector<grid::OccupancyGrid> grids;  // one per group, group frame
  std::vector<Pose2D> local_pose;          // per keyframe, its group's frame
  size_t matched = 0;    // keyframes registered by the scan matcher
  size_t unmatched = 0;  // keyframes whose match was rejected
};

// `groups` partitions 0..keyframes.size()-1, each sorted ascending; W is the
// SSO matrix over the keyframes.
LocalMaps build_local_maps(const Log& log,
                           const std::vector<KeyframeRecord>& keyframes,
                           const std::vector<std::vector<int>>& groups,
                           const area::WeightMatrix& W,
                           const LocalMapOptions& options);

}  // namespace hmt::grouping

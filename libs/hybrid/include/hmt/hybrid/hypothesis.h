// One topological hypothesis of the hybrid filter: a group of particles that
// share a topological path (002 Sec. IV-A: the transition model "can be
// performed only once for groups of particles that share the same
// topological path"), with the HMT map that path implies.
//
// Why groups with their own particle filter. Each hypothesis keeps the full
// particle count for its metric part and resamples within itself; its weight
// is its prior (the transition probability it was born with) times the
// evidence its particles collect (metric_slam::GridRbpf::last_log_evidence).
// Resampling all particles together would let the metric noise of a few
// steps wipe out a topology before the data has spoken; grouped, a topology
// lives until its probability falls under the prune threshold or the
// acceptance (TLCA) settles it, which is the multi-hypothesis behaviour the
// paper asks for. The cost is particles x hypotheses, bounded by
// [hmt] max_hypotheses.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "hmt/metric_slam/grid_rbpf.h"
#include "hmt/tlca/acceptance.h"
#include "hmt/topology/hmt_map.h"
#include "hmt/topology/hypotheses.h"

namespace hmt::hybrid {

// The best particle's path through one visit of an area: poses in the area's
// frame, one per log step from first_step on.
struct TrajectorySegment {
  topology::AreaId area = topology::kNoArea;
  uint64_t first_step = 0;
  std::vector<Pose2D> poses;
  // Per pose, the error the steps moved by the odometry alone have added
  // since the segment began (GridRbpf::blind_trace()); empty when there is
  // none.
  std::vector<Eigen::Matrix3d> blind;
};

struct Hypothesis {
  uint32_t id = 0;
  metric_slam::GridRbpf filter;
  topology::HmtMap map;
  // path = areas entered; log_weight = unnormalised log probability.
  topology::TopologicalHypothesis topo;
  // The log step at which the current area was entered (the particles'
  // paths start there).
  uint64_t area_start_step = 0;
  // Pose of the current area's frame in the area abstraction's frame (a
  // frame continuous across area changes, for the keyframe graph).
  Pose2D aam_from_area;
  // Pose of that frame in the frame of the keyframes the area abstraction
  // is given. Rival hypotheses' frames drift apart (33 m after the Infinite
  // Corridor's last loop), and each keyframe comes from whichever hypothesis
  // is best then: at every keyframe the others are anchored where it puts
  // the robot, so that the keyframes' path does not jump when the best
  // changes. The identity in a hypothesis that was the best at every
  // keyframe.
  Pose2D keyframes_from_aam;
  // Finished visits; shared between hypotheses that branched after them.
  std::vector<std::shared_ptr<const TrajectorySegment>> trajectory;
  // Loop closures made since this hypothesis was last accepted (TLCA).
  std::vector<tlca::ClosureRecord> pending_closures;

  explicit Hypothesis(metric_slam::GridRbpf f) : filter(std::move(f)) {}
  topology::AreaId current_area() const { return topo.current_area(); }
  // A pose in the current area's frame, in the keyframes' frame.
  Pose2D in_keyframes(const Pose2D& in_area) const {
    return keyframes_from_aam + (aam_from_area + in_area);
  }
};

}  // namespace hmt::hybrid

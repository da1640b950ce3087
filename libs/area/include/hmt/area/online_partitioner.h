// Online area detection: the Area Abstraction Mechanism (AAM) of HMT-SLAM.
//
// What the papers say. 000 Sec. 5: at each step a node with the last
// observation and its pose estimate is attached to the auxiliary graph (the
// weight matrix grows by one row and column, Eq. 21) and "the sequence of the
// last robot observations is partitioned to check whether the robot has
// entered into a new area or not"; the matrix size is bounded in practice
// because "eventually the robot moves to a different area and a new matrix is
// created". 002 Sec. IV-A and Fig. 5: the graph of observations is bisected by
// the minimum normalized cut and "the robot has moved to a different area if
// the resulting cut is below a certain limit ... If such a partitioning
// happens, the immediate past of the robot path is updated to the new
// topological position".
//
// How this class reads it:
//  - The graph holds the keyframes of the current area — those since the last
//    new-area event — or only its `window_size` most recent ones when the area
//    is larger (older ones leave the graph but stay members of the area). This
//    bounds the cost per keyframe.
//  - update() bisects that graph once (the first step of 000 Table 1, with
//    the configured split method). The robot has entered a new area when
//      * the bisection's Ncut < tau, and
//      * the side N holding the newest keyframe does not hold the oldest
//        keyframe of the graph (otherwise the robot is back where the current
//        area began: that is still the same area), and
//      * both sides have at least min_cluster_size keyframes.
//    N is "the immediate past" that moves to the new area; its members are
//    grouped by overlap, not by time, so N may include an earlier keyframe
//    that sensed the new area (e.g. through a doorway). Every other keyframe
//    of the current area stays behind.
//  - After a new-area event the graph keeps only N (a new matrix is started
//    from the new area's keyframes, with their edges); the keyframes left
//    behind are dropped from the graph.
//
// The placement policy (options.placement, placement.h) changes the rule:
// `islands` replaces the cut's test by Eq. 3 of 003 at the newest keyframe
// (N is then the bisection's side holding the newest keyframe, whatever its
// Ncut, or the newest keyframe alone when that side holds the oldest), `both` accepts a cut as above only when Eq. 3 also
// fires. Each keyframe carries its epsilon and R (keyframe.h).
//
// Recognising a known area (loop closure) is not decided here: a return to
// an earlier area is reported as a new area, and the topological inference
// (TSBI) decides whether it is one already known.
//
// About tau: with tau = 1 a bisection is accepted as soon as its cut is
// below the geometric mean of the two groups' internal associations (001
// Eq. 12-13) — for two equal halves, as soon as the SSO across the halves is
// on average lower than within them. A room seen from many places is then
// often divided further (001 Fig. 5 has 8 groups for 4 rooms and a
// corridor); lower values (000 suggests 0.2 to 1) give larger areas.
//
// Not synchronised: one thread (the AAM process) owns an instance.
#pragma once

#include <vector>

#include "hmt/area/area_options.h"
#include "hmt/area/keyframe.h"
#include "hmt/area/spectral_bisection.h"
#include "hmt/area/sso_graph.h"

namespace hmt::checkpoint {
struct Access;  // hmt/checkpoint/checkpoint.h
}  // namespace hmt::checkpoint

namespace hmt::area {

struct AreaDecision {
  bool new_area = false;
  // Ncut of the bisection examined (2 when there was nothing to bisect).
  double ncut = 2.0;
  // On a new area: the keyframes that stay in the area being left (all its
  // members not in N, including those already out of the window), and those
  // forming the new area (N, which holds the newest keyframe). Both sorted.
  std::vector<int> stay;
  std::vector<int> new_area_keyframes;
  // The oldest keyframe left in the window after this update: no later
  // decision, nor window(), names an older one, so whoever holds the
  // keyframes' scans by id may let the older ones go.
  int oldest_in_window = 0;
};

class OnlinePartitioner {
  // Checkpoints save and restore every member, bit for bit.
  friend struct hmt::checkpoint::Access;

 public:
  explicit OnlinePartitioner(const AreaOptions& options);

  // Adds the next keyframe and evaluates its row of W. Returns its id: 0 for
  // the first keyframe, then 1, 2, ... in the order added.
  int add_keyframe(const Keyframe& keyframe);

  // Decides, after the newest keyframe, whether the robot entered a new area
  // (see the header comment). On a new area the current area becomes N.
  AreaDecision update();

  // The log is over: the window is bisected once more and the place the
  // robot ended in is returned as a new area, whatever the cut's Ncut: the
  // side holding the newest keyframe, or when that side also holds the
  // oldest, its keyframes newer than the other side's newest. The place
  // where a log ends is often one it has seen before (a tour back to its
  // start, a last corridor driven again); without this, a return made
  // inside the log's last area is never put to the topological inference,
  // and its loop stays open.
  AreaDecision end_of_log();

  // Members of the current area (since the last new-area event), ascending.
  const std::vector<int>& current_area() const { return area_; }
  // The keyframes in the graph (the window), ascending.
  std::vector<int> window() const;
  const SsoGraph& graph() const { return graph_; }
  int keyframe_count() const { return next_id_; }
  const AreaOptions& options() const { return options_; }

 private:
  AreaDecision decide();
  // The window's graph bisected with the configured split method.
  Bisection bisect() const;
  // Fills `d` with the new area made of the window's keyframes at local
  // indices `local` (ascending) and starts the graph again from them.
  void split(const std::vector<int>& local, AreaDecision& d);

  AreaOptions options_;
  SsoGraph graph_;
  std::vector<int> area_;    // current area, ascending
  std::vector<int> window_;  // graph members, ascending (a suffix of area_
                             // after the first new-area event, in general)
  int next_id_ = 0;
  double newest_uncertainty_ = 0.0;      // epsilon of the newest keyframe
  double newest_distinctiveness_ = 0.0;  // its R
};

}  // namespace hmt::area

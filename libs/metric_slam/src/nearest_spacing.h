// Which scan of a log stands for each mark of a spacing (private to this
// library): the filter's updates ([metric_slam] update_distance /
// update_angle) and the matcher's range sample (matching_range.h).
#pragma once

#include "hmt/common/pose2d.h"

namespace hmt::metric_slam {

// Whether a scan `moved` on from the last one taken, `step` on from the scan
// before, is still short of the next mark: the scan taken is the one nearest
// `distance` (taking the next step to be as long as this one), or the first
// at `angle` of turn. So a log thinned to steps a little short of the
// spacing is taken whole, not every other scan, and a log recorded every few
// centimetres is taken every `distance`.
inline bool short_of_nearest_mark(const Pose2D& moved, const Pose2D& step, double distance,
                                  double angle) {
  return within_spacing(moved, distance - 0.5 * step.norm(), angle);
}

}  // namespace hmt::metric_slam

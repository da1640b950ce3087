#include "hmt/grouping/local_maps.h"

#include <algorithm>

#include "hmt/grid/scan_insertion.h"
#include "hmt/metric_slam/scan_points.h"

namespace hmt::grouping {

LocalMaps build_local_maps(const Log& log,
                           const std::vector<KeyframeRecord>& keyframes,
                           const std::vector<std::vector<int>>& groups,
                           const area::WeightMatrix& W,
                           const LocalMapOptions& opt) {
  LocalMaps out;
  out.local_pose.resize(keyframes.size());
  out.grids.reserve(groups.size());
  const metric_slam::ScanMatcher matcher(opt.matcher);
  for (const std::vector<int>& g : groups) {
    out.grids.emplace_back(opt.resolution);
    grid::OccupancyGrid& map = out.grids.back();
    int prev = -1;
    for (int k : g) {
      const KeyframeRecord& kf = keyframes[static_cast<size_t>(k)];
      const LaserScan& scan = log.steps[static_cast<size_t>(kf.scan)].scan;
      Pose2D pose;  // the first keyframe defines the frame
      if (prev >= 0) {
        // Anchor: the earlier group member with the largest SSO with k.
        int anchor = prev;
        double best = 0.0;
        for (area::WeightMatrix::InnerIterator it(W, k); it; ++it) {
          const int j = static_cast<int>(it.row());
          if (j >= k || it.value() < best) continue;
          if (!std::binary_search(g.begin(), g.end(), j)) continue;
          best = it.value();
          anchor = j;  // rows ascend: on a tie the later keyframe wins
        }
        const KeyframeRecord& ak = keyframes[static_cast<size_t>(anchor)];
        pose = out.local_pose[static_cast<size_t>(anchor)] + (kf.pose - ak.pose);
        if (opt.refine) {
          const metric_slam::ScanPoints pts = metric_slam::prepare_scan(
              scan, opt.matcher.max_range, opt.matcher.beam_skip,
              opt.resolution);
          metric_slam::MatchScore score;
          const Pose2D refined = matcher.optimize(map, pose, pts, &score);
          if (!pts.hit.empty() && opt.matcher.tracks(score.matched, pts.hit.size())) {
            pose = refined;
            ++out.matched;
          } else {
            ++out.unmatched;
          }
        }
      }
      out.local_pose[static_cast<size_t>(k)] = pose;
      grid::insert_scan(map, pose, scan, opt.insertion);
      prev = k;
    }
  }
  return out;
}

}  // namespace hmt::grouping

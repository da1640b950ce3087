#include "hmt/tsbi/observations.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

namespace hmt::tsbi {

Observations gather_observations(const std::vector<PosedScan>& scans,
                                 const Pose2D& now, double max_range,
                                 double free_step, int max_points, double evidence_cell) {
  metric_slam::ScanPoints all;
  Observations out;
  for (const PosedScan& ps : scans) {
    if (!ps.scan) continue;
    out.scans.push_back({ps.pose - now, ps.scan});
    const metric_slam::ScanPoints pts =
        metric_slam::prepare_scan(*ps.scan, max_range, 0, free_step);
    const Pose2D rel = ps.pose - now;  // the scan's pose seen from `now`
    for (size_t i = 0; i < pts.hit.size(); ++i) {
      all.hit.push_back(rel.transform(pts.hit[i]));
      all.free.push_back(rel.transform(pts.free[i]));
    }
  }
  out.points = metric_slam::spread_subset(all, max_points);
  if (!out.points.hit.empty())
    out.scale = static_cast<double>(all.hit.size()) / static_cast<double>(out.points.hit.size());
  if (evidence_cell > 0) {
    out.evidence_cell = evidence_cell;
    std::vector<std::pair<int64_t, int64_t>> cells;
    cells.reserve(all.hit.size());
    for (const Point2D& p : all.hit)
      cells.emplace_back(static_cast<int64_t>(std::floor(p.x / evidence_cell)),
                         static_cast<int64_t>(std::floor(p.y / evidence_cell)));
    std::sort(cells.begin(), cells.end());
    out.surface_cells =
        static_cast<size_t>(std::unique(cells.begin(), cells.end()) - cells.begin());
  }
  return out;
}

}  // namespace hmt::tsbi

#include "hmt/metric_slam/scan_points.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace hmt::metric_slam {

ScanPoints prepare_scan(const LaserScan& scan, double max_range, int skip,
                        double free_step) {
  ScanPoints out;
  out.hit.reserve(scan.size());
  out.free.reserve(scan.size());
  const Pose2D& s = scan.sensor_pose;
  for (size_t i = 0; i < scan.size(); i += static_cast<size_t>(skip) + 1) {
    if (!scan.valid[i]) continue;
    const double r = scan.ranges[i];
    if (!(r > 0.0) || r > max_range) continue;
    const double a = scan.bearing(i);
    const double c = std::cos(a), sn = std::sin(a);
    out.hit.push_back(s.transform({r * c, r * sn}));
    out.free.push_back(s.transform({(r - free_step) * c, (r - free_step) * sn}));
  }
  return out;
}

double far_range(const ScanPoints& pts) {
  if (pts.hit.empty()) return 0.0;
  std::vector<double> r;
  r.reserve(pts.hit.size());
  for (const Point2D& p : pts.hit) r.push_back(std::hypot(p.x, p.y));
  const auto at = r.begin() + static_cast<std::ptrdiff_t>(3 * (r.size() - 1) / 4);
  std::nth_element(r.begin(), at, r.end());
  return *at;
}

ScanPoints spread_subset(const ScanPoints& pts, int max_points) {
  const size_t n = pts.hit.size();
  if (max_points <= 0 || n <= static_cast<size_t>(max_points)) return pts;
  const size_t stride = (n + max_points - 1) / static_cast<size_t>(max_points);
  ScanPoints out;
  for (size_t i = 0; i < n; i += stride) {
    out.hit.push_back(pts.hit[i]);
    out.free.push_back(pts.free[i]);
  }
  return out;
}

}  // namespace hmt::metric_slam

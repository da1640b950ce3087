#include "mrpt_map_outputs.h"

#include <cmath>

#include "hmt/io/mrpt_maps.h"

namespace hmt::pipeline {
namespace {

// Cov(area (+) in_area) to first order: the area frame's covariance through
// the composition's Jacobian, plus the in-area pose's own.
Eigen::Matrix3d keyframe_covariance(const global_map::KeyframeNode& n,
                                    const global_map::GlobalPoses& poses,
                                    const global_map::KeyframeGraphOptions& opt) {
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  const auto area = poses.poses.find(n.area);
  if (area != poses.poses.end()) {
    const double c = std::cos(area->second.mean.theta), s = std::sin(area->second.mean.theta);
    Eigen::Matrix3d j = Eigen::Matrix3d::Identity();
    j(0, 2) = -s * n.in_area.x - c * n.in_area.y;
    j(1, 2) = c * n.in_area.x - s * n.in_area.y;
    cov = j * area->second.cov * j.transpose();
  }
  const double d = n.in_area.norm();
  const double sxy = opt.in_area_std_xy + opt.in_area_std_xy_per_metre * d;
  const double sth = opt.in_area_std_theta + opt.in_area_std_theta_per_metre * d;
  cov(0, 0) += sxy * sxy;
  cov(1, 1) += sxy * sxy;
  cov(2, 2) += sth * sth;
  return cov;
}

}  // namespace

std::vector<global_map::KeyframeNode> visit_keyframes(
    const std::vector<global_map::AreaVisit>& visits, const global_map::GlobalPoses& poses,
    const global_map::KeyframeGraphOptions& opt) {
  std::vector<global_map::KeyframeNode> nodes;
  for (size_t v = 0; v < visits.size(); ++v) {
    const global_map::AreaVisit& visit = visits[v];
    const auto area = poses.poses.find(visit.area);
    if (area == poses.poses.end()) continue;  // not placed in the global frame
    // The switching step, shared with the next visit (keyframe_graph.h), is
    // the next visit's first: the trajectory places it in the new area.
    size_t count = visit.poses.size();
    if (count > 0 && v + 1 < visits.size() &&
        visits[v + 1].first_step == visit.first_step + count - 1)
      --count;
    Pose2D last;
    for (size_t i = 0; i < count; ++i) {
      const Pose2D& p = visit.poses[i];
      if (i > 0 && within_spacing(p - last, opt.keyframe_distance, opt.keyframe_angle)) continue;
      last = p;
      global_map::KeyframeNode n;
      n.area = visit.area;
      n.visit = v;
      n.step = visit.first_step + i;
      n.in_area = p;
      n.global = area->second.mean + p;
      nodes.push_back(n);
    }
  }
  return nodes;
}

void write_mrpt_map_outputs(const grid::OccupancyGrid& grid, const grid::MapFrame& frame,
                            const std::vector<global_map::KeyframeNode>& nodes,
                            const global_map::GlobalPoses& poses,
                            const global_map::KeyframeGraphOptions& opt,
                            const global_map::StepSource& steps, const std::string& out_dir) {
  // The frame's cell (0, 0) is the grid's cell (lo_x, lo_y) (map_export.h).
  const int lo_x = static_cast<int>(std::lround(frame.origin_x / frame.resolution));
  const int lo_y = static_cast<int>(std::lround(frame.origin_y / frame.resolution));
  io::MrptGridMap g;
  g.resolution = frame.resolution;
  g.x_min = frame.origin_x;
  g.y_min = frame.origin_y;
  g.size_x = frame.width;
  g.size_y = frame.height;
  g.occupancy = [&](int cx, int cy) {
    return static_cast<float>(grid.probability({lo_x + cx, lo_y + cy}));
  };
  io::write_mrpt_gridmap(g, out_dir + "/map.gridmap.gz");

  std::vector<io::MapKeyframe> keyframes;
  for (const global_map::KeyframeNode& n : nodes) {
    const LogStep* step = steps(n.step);
    if (!step || step->scan.ranges.empty()) continue;
    io::MapKeyframe k;
    k.pose = PoseGaussian(n.global, keyframe_covariance(n, poses, opt));
    k.scan = step->scan;
    k.scan.timestamp = step->timestamp;
    keyframes.push_back(std::move(k));
  }
  io::write_mrpt_simplemap(keyframes, out_dir + "/keyframes.simplemap");
}

}  // namespace hmt::pipeline

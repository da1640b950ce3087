#include "hmt/global_map/keyframe_map.h"

#include <cmath>
#include <stdexcept>

namespace hmt::global_map {

std::vector<Pose2D> keyframe_trajectory(const std::vector<AreaVisit>& visits,
                                        const std::vector<KeyframeNode>& nodes, uint64_t first,
                                        size_t count) {
  // Each visit's nodes (indices, in step order) and its path length from
  // its first step.
  std::vector<std::vector<size_t>> of_visit(visits.size());
  for (size_t i = 0; i < nodes.size(); ++i)
    if (nodes[i].visit < visits.size()) of_visit[nodes[i].visit].push_back(i);
  std::vector<Pose2D> out(count);
  std::vector<char> set(count, 0);
  // Visits in order: a later visit overrides the step it shares with the
  // one before (the switching step, which the later visit owns).
  for (size_t v = 0; v < visits.size(); ++v) {
    const AreaVisit& visit = visits[v];
    const std::vector<size_t>& own = of_visit[v];
    if (own.empty()) continue;
    std::vector<double> along(visit.poses.size(), 0.0);
    for (size_t k = 1; k < visit.poses.size(); ++k)
      along[k] = along[k - 1] + (visit.poses[k] - visit.poses[k - 1]).norm();
    size_t j = 0;  // the last node at or before the step, else the first
    for (size_t k = 0; k < visit.poses.size(); ++k) {
      const uint64_t step = visit.first_step + k;
      if (step < first || step - first >= count) continue;
      while (j + 1 < own.size() && nodes[own[j + 1]].step <= step) ++j;
      // The step seen from node n, placed where the graph put n.
      auto from = [&](size_t n) {
        const KeyframeNode& node = nodes[own[n]];
        return node.global + (visit.poses[k] - node.in_area);
      };
      Pose2D p = from(j);
      if (nodes[own[j]].step < step && j + 1 < own.size()) {
        // Between two nodes: from each, blended by the share of the path
        // between them already driven (of the steps, when the robot turned
        // on the spot), so that the graph's corrections, which differ from
        // node to node, pass smoothly from one to the next.
        const uint64_t s0 = nodes[own[j]].step, s1 = nodes[own[j + 1]].step;
        const double a0 = along[s0 - visit.first_step], a1 = along[s1 - visit.first_step];
        const double f = a1 > a0 ? (along[k] - a0) / (a1 - a0)
                                 : static_cast<double>(step - s0) / static_cast<double>(s1 - s0);
        const Pose2D q = from(j + 1);
        p = Pose2D(p.x + f * (q.x - p.x), p.y + f * (q.y - p.y),
                   wrap_angle(p.theta + f * wrap_angle(q.theta - p.theta)));
      }
      out[step - first] = p;
      set[step - first] = 1;
    }
  }
  for (size_t i = 1; i < count; ++i)
    if (!set[i]) out[i] = out[i - 1];
  return out;
}

grid::OccupancyGrid render_keyframe_grid(const std::vector<KeyframeNode>& nodes,
                                         const StepSource& steps, double resolution,
                                         const grid::InsertionOptions& insertion) {
  if (!(resolution > 0.0) || !std::isfinite(resolution))
    throw std::invalid_argument("render_keyframe_grid: resolution must be positive and finite");
  grid::OccupancyGrid out(resolution);
  for (const KeyframeNode& n : nodes)
    if (const LogStep* s = steps(n.step)) grid::insert_scan(out, n.global, s->scan, insertion);
  return out;
}

}  // namespace hmt::global_map

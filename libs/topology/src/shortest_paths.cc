#include "hmt/topology/shortest_paths.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <queue>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

namespace hmt::topology {

double path_cost(const Eigen::Matrix3d& cov, const PathCostOptions& options) {
  const double l = options.angle_length_scale;
  return cov(0, 0) + cov(1, 1) + l * l * cov(2, 2);
}

std::vector<AreaId> PathTree::path_to(AreaId id) const {
  std::vector<AreaId> path;
  for (AreaId at = id; at != kNoArea;) {
    const auto it = nodes.find(at);
    if (it == nodes.end())
      throw std::out_of_range("PathTree: area " + std::to_string(id) +
                              " is not reachable from area " +
                              std::to_string(root));
    path.push_back(at);
    at = it->second.parent;
  }
  std::reverse(path.begin(), path.end());
  return path;
}

const PoseGaussian& PathTree::pose_of(AreaId id) const {
  const auto it = nodes.find(id);
  if (it == nodes.end())
    throw std::out_of_range("PathTree: area " + std::to_string(id) +
                            " is not reachable from area " +
                            std::to_string(root));
  return it->second.pose;
}

PathTree shortest_paths(const HmtMap& map, AreaId root,
                        const PathCostOptions& options) {
  if (!(options.angle_length_scale > 0.0) ||
      !std::isfinite(options.angle_length_scale))
    throw std::invalid_argument(
        "shortest_paths: angle_length_scale must be positive and finite");
  if (!map.has_area(root))
    throw std::out_of_range("shortest_paths: unknown root area " +
                            std::to_string(root));

  // Adjacency lists (ascending neighbour ids, thanks to the ordered arc map),
  // built once: O(E log V) overall.
  std::map<AreaId, std::vector<AreaId>> adjacency;
  for (const auto& kv : map.arcs()) {
    adjacency[kv.first.first].push_back(kv.first.second);
    adjacency[kv.first.second].push_back(kv.first.first);
  }
  for (auto& kv : adjacency) std::sort(kv.second.begin(), kv.second.end());

  // A tentative label: the area's frame composed along the best path found
  // so far (Eq. 15), its cost, and the parent on that path.
  struct Label {
    double cost;
    size_t hops;
    AreaId parent;
    PoseGaussian pose;
  };
  std::map<AreaId, Label> best;
  std::map<AreaId, bool> done;
  // Min-heap on (cost, id): equal costs settle the smaller id first.
  using Entry = std::pair<double, AreaId>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  best[root] = {0.0, 0, kNoArea, PoseGaussian(Pose2D())};
  queue.emplace(0.0, root);

  PathTree tree;
  tree.root = root;
  while (!queue.empty()) {
    const auto [cost, id] = queue.top();
    queue.pop();
    if (done[id] || cost > best[id].cost) continue;
    done[id] = true;
    // std::map keeps references valid as the neighbours' labels are added.
    const Label& label = best[id];
    PathTree::Node node;
    node.parent = label.parent;
    node.cost = label.cost;
    node.hops = label.hops;
    node.pose = label.pose;
    tree.nodes.emplace(id, node);

    const auto adj = adjacency.find(id);
    if (adj == adjacency.end()) continue;
    for (AreaId next : adj->second) {
      if (done[next]) continue;
      PoseGaussian pose = compose(label.pose, map.arc(id, next));
      const double candidate = path_cost(pose.cov, options);
      const auto it = best.find(next);
      // Strictly better cost wins; an equal cost keeps the parent settled
      // first (settling is in (cost, id) order, so this is deterministic).
      if (it == best.end() || candidate < it->second.cost) {
        best[next] = {candidate, label.hops + 1, id, std::move(pose)};
        queue.emplace(candidate, next);
      }
    }
  }
  return tree;
}

PoseGaussian compose_path(const HmtMap& map, const std::vector<AreaId>& path) {
  if (path.empty()) throw std::invalid_argument("compose_path: empty path");
  if (!map.has_area(path.front()))
    throw std::out_of_range("compose_path: unknown area " +
                            std::to_string(path.front()));
  PoseGaussian pose{Pose2D()};
  for (size_t i = 1; i < path.size(); ++i)
    pose = compose(pose, map.arc(path[i - 1], path[i]));
  return pose;
}

}  // namespace hmt::topology

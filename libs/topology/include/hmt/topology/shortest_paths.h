// Relative poses between non-adjacent areas (002 section IV-A and IV-C,
// Eq. 15): the Dijkstra shortest-path tree from a reference area, and the
// Gaussians composed along its branches.
//
// Eq. 15 (as read here): for a reference area a and an area b reached by the
// topological path a, a_1, ..., a_n, b,
//     Delta_ab = Delta_{a a_1} (+) Delta_{a_1 a_2} (+) ... (+) Delta_{a_n b}
// where Delta_xy is the pose of y's frame in x's frame and (+) the pose
// composition; the arcs are independent (Eq. 11), so the composition of
// their Gaussians is propagated to first order (compose() in
// pose_gaussian.h). The paper takes the path from Dijkstra's algorithm on
// the topological graph; it is what TSBI uses as the prior of where a
// candidate area lies for a loop closure, and what draws the shortest-path
// global map.
//
// Path cost: "shortest" should mean "most certain", so the cost of a path
// is that of the Gaussian composed along it,
//     cost = Sigma_xx + Sigma_yy + l^2 Sigma_thth
// the trace of the composed covariance with the heading variance turned
// into m^2 by a length scale l (metres per radian, default 1 m). Why the
// trace: a rotation keeps it, it is non-negative, and the log-determinant
// is negative for small covariances. Why the composed covariance and not a
// sum of per-arc costs: the composition adds lever-arm terms, a heading
// error times the distance still to go, which depend on the whole path. On
// a long loop closed by fine alignments the arcs are millimetre-certain in
// position but not in heading: a sum of arc traces preferred fourteen such
// arcs round the loop (trace 0.015) to the one direct arc between two
// neighbours (0.11), and the composed prior came out 2.3 m wide, too wide
// and too far off for the neighbour to be found (Infinite Corridor soak,
// third lap). Dijkstra here settles areas in order of their composed cost,
// relaxing each neighbour by one composition; the lever-arm terms can make
// a cost fall along a path (through correlations), so the tree is a greedy
// one rather than a proven optimum, but every cost it compares is that of a
// real composed Gaussian.
//
// Ties are broken deterministically: areas are settled in (cost, id) order,
// and an alternative of equal cost never replaces the parent found first.
#pragma once

#include <map>
#include <vector>

#include "hmt/topology/hmt_map.h"

namespace hmt::topology {

struct PathCostOptions {
  double angle_length_scale = 1.0;  // l above, metres per radian (> 0)
};

// The cost of a (composed) Gaussian with covariance `cov`.
double path_cost(const Eigen::Matrix3d& cov,
                const PathCostOptions& options = {});

struct PathTree {
  struct Node {
    AreaId parent = kNoArea;  // kNoArea for the root
    double cost = 0.0;        // path_cost() of `pose` (0 for the root)
    size_t hops = 0;          // arcs from the root
    PoseGaussian pose;        // this area's frame in the root's frame (Eq. 15)
  };

  AreaId root = kNoArea;
  // Every area reachable from the root (the root included, with the identity
  // pose and zero covariance); unreachable areas are absent.
  std::map<AreaId, Node> nodes;

  bool reaches(AreaId id) const { return nodes.count(id) != 0; }
  // Root, ..., id. Throws std::out_of_range if id is not reached.
  std::vector<AreaId> path_to(AreaId id) const;
  // Throws std::out_of_range if id is not reached.
  const PoseGaussian& pose_of(AreaId id) const;
};

// Dijkstra from `root` over the arcs of `map`. Throws std::out_of_range if
// root is not an area of the map, std::invalid_argument for a bad option.
PathTree shortest_paths(const HmtMap& map, AreaId root,
                        const PathCostOptions& options = {});

// Eq. 15 along an explicit path of adjacent areas: the pose of path.back()'s
// frame in path.front()'s frame. A one-area path gives the exact identity.
// Throws std::out_of_range if two consecutive areas are not adjacent, and
// std::invalid_argument for an empty path.
PoseGaussian compose_path(const HmtMap& map, const std::vector<AreaId>& path);

}  // namespace hmt::topology

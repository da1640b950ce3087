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
// Edge cost: "shortest" should mean "most certain", so the cost of an arc is
//     cost = Sigma_xx + Sigma_yy + l^2 Sigma_thth
// the trace of its covariance with the heading variance turned into m^2 by a
// length scale l (metres per radian, default 1 m). Why the trace: under
// composition the translational block of the composed covariance is the sum
// of the arcs' translational blocks, each rotated (and a rotation keeps the
// trace), plus lever-arm terms from the heading uncertainty; headings compose
// by addition, so their variances add exactly. The trace is therefore
// additive along a path up to the lever-arm terms, and it is non-negative:
// both are what Dijkstra's optimal-substructure needs. The log-determinant
// was rejected: it is not additive under composition (det(A + B) is not
// det A det B) and is negative for small covariances, which Dijkstra cannot
// take. The lever-arm terms depend on the whole path and cannot be an edge
// cost; the composed covariance reported for each area does include them.
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

// The Dijkstra edge cost of an arc with covariance `cov`.
double arc_cost(const Eigen::Matrix3d& cov,
                const PathCostOptions& options = {});

struct PathTree {
  struct Node {
    AreaId parent = kNoArea;  // kNoArea for the root
    double cost = 0.0;        // sum of arc costs from the root
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

// Global coordinates of the areas of an HMT map (002 section IV-C): the pose
// of every area's frame in the frame of one reference area, the root, with
// its uncertainty. The HMT map itself never needs them (the robot is always
// located in its current area's frame); they are for drawing one global map
// and for inspecting the map as a whole.
//
// Two methods, as in the paper:
//
// 1. shortest_path_poses(): Dijkstra's tree from the root, each area's pose
//    composed along its branch (Eq. 15, topology::shortest_paths). Every arc
//    off the tree is ignored, so a loop shows up as an inconsistency between
//    the two areas whose arc closes it (Fig. 7(c)-(d)).
//
// 2. optimize_poses(): a globally consistent estimate that uses every arc
//    (the method for networks of laser scans the paper cites, [35]). Each arc
//    a -> b is a relative-pose constraint with residual
//        e_ab = [ R_a^T (t_b - t_a) ; wrap(theta_b - theta_a) ] - mu_ab
//    (the pose of b seen from a, (-)x_a (+) x_b, minus the arc's mean, in the
//    (x, y, theta) space the arc's covariance lives in, see pose_gaussian.h),
//    weighted by the arc's information Omega_ab = Sigma_ab^-1. The sum
//        chi2 = sum_ab e_ab^T Omega_ab e_ab
//    is minimised by Gauss-Newton: linearise every residual at the current
//    poses (analytic Jacobians), solve the normal equations H dx = -g for
//    all poses at once, update, repeat. It starts from the shortest-path
//    tree, which is exact on the tree's arcs, so only the loops' misfit has
//    to be spread out, and a few iterations suffice.
//
// Why CHOLMOD: H has one 3x3 block per area on the diagonal and one pair of
// off-diagonal blocks per arc. An HMT map's areas are places (rooms,
// corridor stretches) and each is adjacent to only a few others, so H is
// very sparse and stays so as the map grows; a sparse Cholesky factorisation
// with a fill-reducing ordering (SuiteSparse CHOLMOD, AMD) costs about
// O(areas) for such graphs where a dense one costs O(areas^3). The pattern
// of H does not change between iterations, so it is analysed once and only
// refactorised numerically. The same factor then gives each area's
// covariance, the 3x3 diagonal block of H^-1, by solving for that area's
// three columns (never forming the dense inverse).
//
// Why the root is fixed: the arcs only constrain relative poses, so chi2 is
// unchanged if every pose is moved by the same rigid transform; H is then
// singular (three zero eigenvalues, the gauge freedom). Holding the root at
// the identity removes exactly that freedom and makes H positive definite
// whenever every area is connected to the root. It is also what a global
// pose means here: the pose of an area in the root's frame, with the root
// itself known exactly (identity, zero covariance), which is what
// shortest_path_poses() gives too, so the two methods are comparable.
//
// Areas not connected to the root by arcs have no pose in its frame; both
// methods list them in `unreachable`. All containers are ordered by id, so
// the results are deterministic.
#pragma once

#include <Eigen/Core>
#include <map>
#include <vector>

#include "hmt/topology/hmt_map.h"
#include "hmt/topology/pose_gaussian.h"

namespace hmt::global_map {

using topology::AreaId;

struct GlobalPoses {
  AreaId root = topology::kNoArea;
  // Each reachable area's frame in the root's frame; the root itself is the
  // identity with zero covariance.
  std::map<AreaId, topology::PoseGaussian> poses;
  // Areas with no path of arcs to the root, ascending.
  std::vector<AreaId> unreachable;
};

// Method 1: the Dijkstra tree of topology::shortest_paths (Eq. 15). Throws
// std::invalid_argument if `root` is not an area of the map.
GlobalPoses shortest_path_poses(const topology::HmtMap& map, AreaId root);

struct PoseGraphOptions {
  // Upper bound on Gauss-Newton iterations (>= 1).
  int max_iterations = 50;
  // Stop when an iteration lowers chi2 by less than this fraction of its
  // previous value (> 0, < 1).
  double relative_tolerance = 1e-9;
};

struct PoseGraphReport {
  int iterations = 0;        // Gauss-Newton steps taken
  double initial_chi2 = 0.0;  // at the shortest-path tree
  double final_chi2 = 0.0;
  // True if the relative-change test stopped the iterations (or no step
  // could lower chi2 any further); false if max_iterations ran out first.
  bool converged = false;
};

// Method 2: the globally consistent estimate described above, root fixed,
// started from shortest_path_poses(). Covariances are the marginals of the
// final information matrix. `report` may be null. Throws
// std::invalid_argument for an unknown root or bad options, and
// std::runtime_error if the information matrix cannot be factorised (it is
// positive definite for any map whose arcs have positive definite
// covariances, so this signals a numerically degenerate map).
GlobalPoses optimize_poses(const topology::HmtMap& map, AreaId root,
                           const PoseGraphOptions& options = {},
                           PoseGraphReport* report = nullptr);

// The residual e_ab above of one arc of `map` at the given poses (both ends
// must be in `poses`; throws std::out_of_range otherwise).
Eigen::Vector3d arc_residual(const topology::Arc& arc,
                             const GlobalPoses& poses);

// chi2 above over every arc whose two ends are both in `poses`.
double chi2(const topology::HmtMap& map, const GlobalPoses& poses);

}  // namespace hmt::global_map

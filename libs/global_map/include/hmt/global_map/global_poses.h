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
// Robustness: a false loop closure must not bend the map. A loop closure
// that TSBI and TLCA accepted wrongly (a look-alike room, a repeated
// corridor) is an arc whose mean is metres or tens of degrees off, often
// with a small covariance (a fine alignment's). Plain least squares spreads
// its misfit over the loop, pulling every area of it out of place. So
// optimize_poses() tests the arcs for gross errors and switches off those
// that fail, as switchable constraints do (s = 0), one at a time:
//
// 1. Which arcs are tested: the loop arcs only, i.e. every arc but an
//    area's creating arc (area.frame.parent -> area, the crossing at which
//    the robot entered the area for the first time). The creating arcs are
//    the odometry chain: measured by the metric filter tracking the robot
//    across the crossing, never by recognising a place, so they cannot be a
//    false loop closure; they form a spanning tree, so each is the only
//    link of some part of the map when the closures are set aside; and in a
//    single loop every arc's test statistic below is the same number (each
//    is predicted by all the others), so geometry alone cannot say whether
//    the chain or the closure is wrong -- the prior does, and the decision
//    that can be wrong is the closure. A closure later fused into a creating
//    arc (a loop closed through the areas' own crossing) is gated by TLCA
//    against that arc before it is fused (tlca/acceptance.h).
//
// 2. The statistic: the normalised residual of the arc (Baarda's data
//    snooping in geodetic networks), w = e^T (Sigma_ab - J P J^T)^-1 e at
//    the least-squares estimate, with P the estimate's covariance over both
//    ends (blocks of H^-1) and J the residual's Jacobian. Sigma_ab - J P J^T
//    is the covariance of the residual; with S the covariance of the
//    prediction of the arc by the rest of the map (every other path between
//    its ends), w equals the squared Mahalanobis distance of the arc's mean
//    from that prediction under Sigma_ab + S: a chi-square with 3 degrees
//    of freedom for a correct arc. A long loop with drift has a large S and
//    passes; a wrong closure in the same building does not. An arc with no
//    redundancy (no other path: Sigma_ab - J P J^T = 0) cannot be tested.
//    The model tested has a floor F = diag(outlier_floor_xy^2,
//    outlier_floor_xy^2, outlier_floor_theta^2) added to the covariance of
//    every loop arc (in its stored direction, from < to), and is fitted by
//    least squares for the test alone (the estimate returned is the fit of
//    the arcs' own covariances): a fine alignment's covariance comes from
//    the grids' Hessian and claims millimetres, while the area maps
//    themselves are off by centimetres and hundredths of a radian (on the
//    Malaga log, TLCA aligned area 11 to area 12 twice, with 2 mm
//    covariances, 8.7 cm apart: chi2 200 without the floor, 3 with it).
//    The floor is far below the errors this is for. It goes on every loop
//    arc, not only the one tested: with the rest of the map left
//    overconfident, a precise correct closure predicted through other
//    precise closures scored above a planted false one on the MIT corridor
//    and was switched off in its place.
//
// 3. The decision: the arc with the largest w above outlier_chi2 is
//    switched off (a single gross error inflates the residuals of its
//    neighbours too, so only the worst is taken), the least squares is
//    solved again without it from the shortest-path tree of the remaining
//    arcs, and the test repeats until no arc fails. When no arc fails the
//    first time, the result is the plain least-squares estimate exactly.
//
// Why not a robust kernel on the arc's own chi2 (Dynamic Covariance
// Scaling, s = min(1, 2 Phi / (Phi + chi2_ab)); Cauchy, Huber by IRLS):
// the weight is a function of the arc's share of the loop misfit, e^T
// Omega_ab e, and a closure whose covariance is small next to the chain's
// (a fine alignment: centimetres; a chain of ten crossings: decimetres)
// takes almost none of it at the least-squares estimate, so started from
// the tree (or from the plain estimate) it keeps full weight and the chain
// bends. Started from the odometry chain instead, the kernel sees the whole
// drift on the closure and switches off correct closures once the drift
// exceeds about sqrt(2 Phi sigma_closure sigma_chain), well inside the
// chain's own uncertainty. The normalised residual weighs the misfit by the
// uncertainty of both the arc and the rest of the map, which is the right
// yardstick either way. And an outlier is switched off rather than scaled
// down to consistency: inflating a precise wrong closure only until it
// passes the gate still pulls the loop by a good part of its error.
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
  // Test the loop arcs and switch off gross errors (see the top). Off: the
  // plain least squares over every arc.
  bool robust = true;
  // A loop arc whose normalised residual (chi-square, 3 degrees of freedom
  // for a correct arc) exceeds this is an outlier (> 0). The default is the
  // 1 - 1e-6 quantile: the arcs' covariances are somewhat optimistic on
  // real logs (at the plain estimate, chi2 per degree of freedom is about
  // 2 on the Intel lab), and a correct closure switched off costs accuracy,
  // while the errors this is for are metres off and score in the thousands.
  double outlier_chi2 = 30.66;
  // The floor F of the test (see the top): a model error of the arcs, in
  // metres and radians (>= 0).
  double outlier_floor_xy = 0.05;
  double outlier_floor_theta = 0.02;
};

// An arc the robust estimate switched off, with its normalised residual
// when it was (see the top).
struct OutlierArc {
  AreaId from = topology::kNoArea;
  AreaId to = topology::kNoArea;
  double chi2 = 0.0;
};

struct PoseGraphReport {
  int iterations = 0;        // Gauss-Newton steps taken, every solve
  double initial_chi2 = 0.0;  // at the shortest-path tree, every arc
  // At the estimate, over the arcs it used (every arc but `outliers`).
  double final_chi2 = 0.0;
  // True if the relative-change test stopped the iterations (or no step
  // could lower chi2 any further); false if max_iterations ran out first.
  bool converged = false;
  // Loop arcs that were tested (robust only; those with redundancy).
  int tested_arcs = 0;
  // Largest normalised residual of a tested arc at the returned estimate
  // (0 when none was tested).
  double max_arc_chi2 = 0.0;
  // The arcs switched off, in the order they were (robust only).
  std::vector<OutlierArc> outliers;
};

// Method 2: the globally consistent estimate described above, root fixed,
// started from shortest_path_poses(), robust to false loop closures unless
// options.robust is off. Covariances are the marginals of the final
// information matrix (without the arcs switched off). `report` may be null. Throws
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

// Whether `arc` is an area's creating arc (area.frame.parent -> area, in
// either direction): the odometry chain, never tested for outliers.
bool is_chain_arc(const topology::HmtMap& map, const topology::Arc& arc);

// chi2 above over every arc whose two ends are both in `poses`.
double chi2(const topology::HmtMap& map, const GlobalPoses& poses);

}  // namespace hmt::global_map

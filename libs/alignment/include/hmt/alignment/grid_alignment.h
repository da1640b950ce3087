// Fine alignment of two local occupancy grids: the step of loop-closure
// acceptance (TLCA, paper 002 section V) that refines the relative pose of
// two areas a loop closure joins before their arc is fused.
//
// Given `moving` and `fixed` and a Gaussian guess of the pose of moving's
// frame in fixed's frame, align_grids() returns the refined pose with a
// covariance, or ok = false with a reason.
//
// Method.
//  1. Points: every occupied cell of each grid (p(occ) > occupied_probability,
//     at least min_hits laser hits), at its mean hit position (sub-cell
//     precision). Cells are visited in a fixed order, so the point lists and
//     everything after them are deterministic.
//  2. Registration: classic point-to-point ICP (icp.h; the schedule of MRPT's
//     CICP, icpClassic), started at the initial mean: every moving point
//     paired with its nearest fixed point within a coarse-to-fine pairing
//     threshold, rigid fit in closed form. The threshold starts at
//     icp_threshold_start (+ icp_threshold_angular per metre from moving's
//     origin, for the rotational error of the guess) and is multiplied by
//     icp_threshold_decay each time the pose stops changing, until it falls
//     below icp_threshold_end (or icp_max_iterations). Every moving point
//     is paired (no decimation).
//  3. Refinement and covariance: Gauss-Newton on the pairs
//     (each moving point with its nearest fixed point within match_distance,
//     searched in the fixed grid's cells around it), with Cauchy weights
//     w = 1 / (1 + (r / robust_scale)^2). The residual depends on the fixed
//     point's neighbourhood (its fixed points within normal_radius):
//     - a wall (the scatter is thin: smallest/largest eigenvalue < 0.1):
//       point-to-line, r = n^T (R p + t - q), n the wall normal;
//     - a corner (>= 3 points, not thin: corners, pillars, clutter):
//       point-to-point, r = R p + t - q;
//     - isolated (< 3 points: stray hits, or a wall seen at a grazing angle
//       whose hits are metres apart): no residual, since which stray hit
//       pairs with which is arbitrary and would fake a constraint. The pair
//       still counts as an inlier.
//     Why not ICP's own covariance, and why not point-to-point everywhere:
//     with point-to-point residuals every pair constrains both translations
//     (J = [I, dR/dtheta p]), so the Hessian of a long featureless corridor
//     still looks well conditioned along the corridor; MRPT's ICP covariance
//     (icpCovLinealMSE / finite differences) is point-to-point too and uses
//     a fixed point variance instead of one measured from the residuals.
//     Point-to-line residuals carry no information along a wall, so the
//     Hessian sees the directions the map does not constrain, which is what
//     the acceptance process needs to know. The refinement moves the ICP
//     result by millimetres (on the test room: ICP alone is within 4 mm,
//     after refinement within 1 mm); it exists so that the Hessian is
//     evaluated at the minimum of the cost it belongs to.
//  4. Covariance: cov = covariance_inflation * sigma^2 * H^-1
//     + diag(sigma_floor_xy^2, sigma_floor_xy^2, sigma_floor_theta^2),
//     with H = sum w J^T J and sigma^2 = sum w r^2 / (m - 3) over the m
//     residual components at the solution. The inflation accounts for the
//     pairs not being independent measurements: neighbouring cells of a wall
//     share the same laser beams, poses and hit-mean quantisation, so the
//     effective number of independent residuals is several times smaller
//     than m (default 5: a wall's error is correlated over a few cells). The
//     floor keeps the result positive definite when the residuals are
//     (nearly) zero, e.g. two grids made from the same noiseless scans.
//  5. Acceptance (ok = false, with `reason`, on the first that fails):
//     - either grid has fewer than min_points points ("too few points");
//     - fewer than min_points pairs at the solution ("too few matches");
//     - inlier_ratio (moving points with a fixed point within
//       match_distance, over the moving points in the overlap) <
//       min_inlier_ratio. The overlap: moving points with a fixed cell
//       within match_distance that the fixed grid has observed (free or
//       occupied). A moving wall that falls where the fixed grid saw free
//       space contradicts the alignment; one that falls where it saw nothing
//       says nothing about it. Over all moving points instead, a true
//       closure between two areas that share only a doorway or a corridor
//       end (most of one grid outside the other) looks like a wrong one:
//       on the fhw log a closure the loop confirms (chi2 0.6) paired 0.24
//       of all its points, 0.90 of those in the overlap. The true closures
//       of the shared logs pair 0.71-0.99 of the overlap (default: half);
//     - the problem is ill-conditioned (a single wall, a featureless
//       corridor: the grids do not fix the pose, and a small-looking
//       covariance would be a lie): H singular; or information_ratio, the
//       smallest over the largest eigenvalue of the (x, y) information with
//       the rotation marginalised out (Schur complement), below
//       min_information_ratio (room: 0.26; corridor with a few niches:
//       0.28; plain corridor: 0.002 and a single wall: 0.0001, not exactly 0
//       because estimated wall normals are slightly tilted by noise); or a
//       standard deviation above max_sigma_xy / max_sigma_theta;
//     - the result moved implausibly far from the guess: the squared
//       Mahalanobis distance d^T (initial.cov + cov)^-1 d, d =
//       difference(result, initial.mean), exceeds gate_chi2 (default: the
//       99.9% quantile of chi^2 with 3 degrees of freedom). A fine alignment
//       must not jump to another local minimum (another doorway, a shifted
//       copy of a repetitive corridor).
//
// Deterministic: no random numbers, no threads; the same inputs give
// bit-identical results.
//
// Thread safety: align_grids only reads its inputs; concurrent calls on the
// same grids are fine.
#pragma once

#include <string>
#include <vector>

#include "hmt/common/config.h"
#include "hmt/grid/occupancy_grid.h"
#include "hmt/topology/pose_gaussian.h"

namespace hmt::alignment {

struct AlignmentOptions {
  // --- points
  double occupied_probability = 0.65;  // a cell above this p(occ) is a point
  int min_hits = 1;                    // ... and has at least this many hits
  int min_points = 50;                 // fewer points (or pairs): not ok

  // --- registration (classic ICP, coarse to fine: icp.h)
  double icp_threshold_start = 1.0;     // initial pairing distance [m]
  double icp_threshold_angular = 0.05;  // + this [rad] x distance from
                                        //   moving's origin [m]
  double icp_threshold_decay = 0.5;     // factor when the pose settles
  double icp_threshold_end = 0.05;      // stop below this [m]
  int icp_max_iterations = 200;

  // --- refinement, statistics and covariance
  int refine_iterations = 10;       // Gauss-Newton steps at most
  double match_distance = 0.15;     // a pair (inlier) is within this [m]
  double normal_radius = 0.30;      // neighbourhood for wall normals [m]
  double robust_scale = 0.05;       // Cauchy kernel scale [m]
  double covariance_inflation = 5.0;  // for correlated neighbouring cells
  double sigma_floor_xy = 0.002;      // [m], added in quadrature
  double sigma_floor_theta = 0.001;   // [rad], added in quadrature

  // --- acceptance
  double min_inlier_ratio = 0.5;   // of the moving points in the overlap
  double gate_chi2 = 16.27;        // squared Mahalanobis gate (3 dof, 99.9%)
  double min_information_ratio = 0.01;  // below: ill-conditioned (see top)
  double max_sigma_xy = 0.10;      // [m]   above: ill-conditioned
  double max_sigma_theta = 0.02;   // [rad] above: ill-conditioned

  // Reads every key above from `section` (same names); throws ConfigError
  // for a value out of range.
  void load(Config& cfg, const std::string& section = "alignment");
};

struct AlignmentResult {
  bool ok = false;
  // The refined pose of moving's frame in fixed's frame and its covariance
  // (positive definite when ok). When not ok: the best estimate reached
  // before the failing check (the initial guess if registration never ran),
  // for diagnostics only.
  topology::PoseGaussian pose;
  double inlier_ratio = 0.0;  // moving points paired at the solution / in
                              //   the overlap (see 5.)
  int overlap_points = 0;     // moving points in the overlap at the solution
  int iterations = 0;         // ICP iterations + Gauss-Newton steps
  double rmse = 0.0;          // RMS residual at the solution of the pairs
                              //   with a wall or corner (see 3.) [m]
  double information_ratio = 0.0;  // conditioning of (x, y), see the top
  int moving_points = 0;      // points extracted from each grid
  int fixed_points = 0;
  std::string reason;         // why not ok; empty when ok
};

// The occupied cells' hit means (p(occ) > occupied_probability, hits >=
// min_hits), in a fixed order (tile rows, then the cells of each tile row by
// row): the same grid always gives the same list.
std::vector<Point2D> occupied_points(const grid::OccupancyGrid& grid,
                                     const AlignmentOptions& opt);

// Throws std::invalid_argument when initial.cov is not positive definite
// (the gate needs it).
AlignmentResult align_grids(const grid::OccupancyGrid& moving,
                            const grid::OccupancyGrid& fixed,
                            const topology::PoseGaussian& initial,
                            const AlignmentOptions& opt);

}  // namespace hmt::alignment

// Topological loop-closure acceptance (TLCA, 002 Sec. IV-D and V): when the
// filter's hypotheses about the topological path are settled enough, part of
// the structure is accepted as definitively correct. Then
//  - each loop closure the accepted hypothesis made is fine-aligned: the
//    local grid of the area the robot left is registered against the grid of
//    the known area it closed into, and that measurement replaces the coarse
//    one TSBI put into the arc (fused, Eq. 10, with whatever the arc held
//    before this crossing);
//  - the hypotheses' shared history is forgotten (topology::
//    forget_common_history), so memory does not grow with the path.
//
// Geometric consistency. Accepting a hypothesis settles which area the
// robot was in, not that each closure's relative pose is right, and one
// wrong closure fused with a fine alignment's centimetre covariance would
// bend every loop through it. So a closure's measurement (the aligned one,
// or TSBI's when alignment failed) is checked before it is fused:
//  (a) the grids: when the alignment ran (both areas archived, enough
//      points) and fewer than alignment.min_inlier_ratio of `from`'s
//      occupied cells in the overlap (where `to` has observed anything,
//      grid_alignment.h) have one of `to`'s within match_distance at its
//      solution, the two grids contradict each other where the closure puts
//      them
//      (the alignment's "inlier ratio" failure, and most "too few matches"
//      ones). The alignment's own threshold is used: it is the overlap it
//      needs to trust its result, and a second one could only disagree with
//      it. An ill-conditioned
//      alignment (a corridor) or a nearly empty grid is no evidence either
//      way and does not fail (a).
//  (b) the loop: the pose of `to` in `from` composed along the shortest
//      path of the map without this closure's arc (with what the arc held
//      before this crossing, if anything; topology::shortest_paths, Eq. 15)
//      is a Gaussian P; the closure agrees with the map when the squared
//      Mahalanobis distance d^T (Sigma + P.cov + F)^-1 d, d = measurement -
//      P, is within consistency_chi2. A long loop composes a large
//      covariance, so its drift passes; a wrong closure in the same
//      building does not. F = diag(consistency_floor_xy^2, ..xy^2,
//      ..theta^2) is the area maps' own error, which a fine alignment's
//      covariance (the grids' Hessian: millimetres) leaves out: on the
//      Malaga log area 11 aligned to area 12 twice, with 2 mm covariances,
//      8.7 cm apart (chi2 200 without F, 3 with it). F is also added to
//      every loop arc of the path (every arc but an area's creating arc)
//      before it is composed, since those are alignments too. The same test
//      as the robust global estimate's (global_map/global_poses.h), with the
//      same defaults. When no other path exists the closure closes no loop:
//      only (a).
//
// An inconsistent closure is still fused, with its covariance inflated to
//     Sigma' = Sigma + P.cov + F + d d^T
// (for (a) alone, without a path, Sigma is kept: a bridge between two parts
// of the map closes no loop and cannot bend it). Why not drop it: the
// hypothesis was accepted, the robot did cross from `from` into `to`'s frame
// and its particles now live there, so the HMT map must hold that arc (an
// area whose crossing has no arc breaks the path, the global map and the
// arcs TSBI later composes its priors from). Why not keep the measurement
// as it is and leave the rest to the robust global estimate: TSBI's priors
// use the arcs directly (Dijkstra on their covariances), long before any
// global estimate. With Sigma', the arc agrees with the rest of the map
// (its Mahalanobis distance from P is below 1 whatever d is), Dijkstra
// prefers the path to it (Sigma' is larger than P.cov), and the pull it
// exerts on the loop in a least-squares fit is about d / (2 + chi2): 3 cm
// for a closure 3 m off at chi2 100, tapering to zero for grosser errors.
// Fused with an earlier arc, it leaves that arc nearly as it was. The report
// says so (consistent = false, reason).
//
// When is a hypothesis "highly dominant (or unique)"? Two policies:
//  - kProbability: its probability reaches accept_probability; the others
//    are dropped. Before that, the loop closures that hypotheses of
//    accept_probability in all share (made by their common ancestor, so the
//    most probable one's first closures) are accepted alone, and the
//    hypotheses without them dropped: which area the robot entered then is
//    settled, whatever the hypotheses still dispute since
//    (hybrid::HybridFilter::accept_shared_closures).
//  - kUnique: only when it is the last one left (the others were pruned for
//    falling under the filter's prune threshold).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "hmt/alignment/grid_alignment.h"
#include "hmt/common/config.h"
#include "hmt/topology/closure_record.h"
#include "hmt/topology/hmt_map.h"

namespace hmt::tlca {

enum class AcceptancePolicy { kProbability, kUnique };

struct TlcaOptions {
  AcceptancePolicy policy = AcceptancePolicy::kProbability;
  double accept_probability = 0.99;
  bool fine_alignment = true;
  // The checks (a) and (b) above.
  bool consistency_check = true;
  // The gate of (b) on the squared Mahalanobis distance (> 0): the 1 - 1e-6
  // quantile of chi-square with 3 degrees of freedom, since the arcs'
  // covariances are somewhat optimistic on real logs and a correct closure
  // held back costs the loop, while a wrong one is metres off.
  double consistency_chi2 = 30.66;
  // F of (b), in metres and radians (>= 0).
  double consistency_floor_xy = 0.05;
  double consistency_floor_theta = 0.02;
  alignment::AlignmentOptions alignment;
  // Reads [tlca] (policy = probability | unique, accept_probability,
  // fine_alignment, consistency_check, consistency_chi2,
  // consistency_floor_xy, consistency_floor_theta) and the alignment's own
  // section ([alignment]).
  void load(Config& cfg, const std::string& section = "tlca");
};

// The index of the hypothesis to accept among `probabilities` (normalised),
// or nothing. With one hypothesis it is always accepted.
std::optional<size_t> dominant(const std::vector<double>& probabilities,
                               const TlcaOptions& options);

// A loop closure made by TSBI on one hypothesis (topology/closure_record.h).
using ClosureRecord = topology::ClosureRecord;

struct ClosureReport {
  ClosureRecord record;
  bool aligned = false;        // fine alignment succeeded and was used
  // Passed (a) and (b) above (true when consistency_check is off).
  bool consistent = true;
  // Why not aligned, and why inconsistent (joined by "; "); empty when
  // aligned and consistent.
  std::string reason;
  topology::PoseGaussian used; // the measurement fused into the arc
  double correction_m = 0.0;   // how far alignment moved `to`'s origin
  double correction_rad = 0.0;
  // The alignment's inlier ratio over the overlap and the overlap's size
  // (moving points; 0 when the alignment did not run).
  double inlier_ratio = 0.0;
  int overlap_points = 0;
  // (b): the arcs of the other path (0: none, only (a) applied) and the
  // squared Mahalanobis distance of the measurement from it.
  size_t loop_hops = 0;
  double loop_chi2 = 0.0;
};

// The two halves of accept_closure, so the costly one can run on its own
// thread (the framework's TLCA process) over a snapshot of the map:
// align_closure fine-aligns the two areas' archived grids (when both exist
// and the option is on), checks the result against the grids and the map
// (above) and says which measurement to use (the aligned one, or TSBI's
// when alignment failed; inflated when inconsistent); apply_closure
// rewrites the arc from..to as arc_before (+) that measurement.
ClosureReport align_closure(const topology::HmtMap& map, const ClosureRecord& closure,
                            const TlcaOptions& options);
void apply_closure(topology::HmtMap& map, const ClosureReport& report);

// align_closure then apply_closure on the same map.
ClosureReport accept_closure(topology::HmtMap& map, const ClosureRecord& closure,
                             const TlcaOptions& options);

}  // namespace hmt::tlca

// The modes of F(gamma) over the whole prior window of a candidate area
// (002 Sec. IV-A), found exactly: a multi-resolution branch and bound over a
// lattice of poses (Cartographer's FastCorrelativeScanMatcher2D, Olson's
// multi-resolution correlative matcher), whose maxima start the matcher's
// refinement (transition_model.h).
//
// The lattice: every heading center.theta + t st and translation
// center + (i, j) s res, s whole cells, |t| <= nt, |i| <= nx, |j| <= ny,
// the box around the prior's gate, of which only the poses inside the gate
// (squared Mahalanobis distance to the prior mean at most `gate`) count.
// A pose's cost is the sum of its points' costs (cost_stack.h); the scan is
// rotated once per heading, and a translation by whole cells moves every
// point's cell by the same whole cells.
//
// The modes: the lattice poses in ascending cost (ties in lattice order:
// t, then j, then i ascending), each kept unless it lies near one kept
// before (closer than the separation in x, y and heading), at most `count`,
// none costlier than `max_cost` nor than the best mode's cost + `margin`. exhaustive_modes() computes exactly
// that by scoring every pose; bnb_modes() gets the same answer from a
// best-first branch and bound over blocks of 2^k x 2^k translations at one
// heading, each bounded below by the cost stack's level k (never above the
// cost of any pose in the block): blocks are expanded in order of their
// bound, a block before a pose of equal cost, so the poses come out in the
// exhaustive order and the search stops at the count-th mode. Blocks that
// miss the gate ellipsoid (its exact minimum over the block at that
// heading), that lie wholly near the modes found, or whose bound exceeds
// the cost limit are never expanded; once the best mode is out, the limit
// tightens to its cost + margin (the other modes are what makes most of the
// work: the bound must rule out every block that could hold a maximum
// cheaper than the last one kept).
#pragma once

#include <Eigen/Core>
#include <climits>
#include <cstdint>
#include <vector>

#include "hmt/common/pose2d.h"
#include "hmt/topology/pose_gaussian.h"
#include "hmt/tsbi/cost_stack.h"
#include "hmt/tsbi/match_field.h"

namespace hmt::tsbi {

struct SearchLattice {
  Pose2D center;  // the prior mean
  double resolution = 0.05;
  int step_cells = 1;      // translation step (cells)
  double step_theta = 0.01;
  int nx = 0, ny = 0, nt = 0;  // half-extents (steps)
  Eigen::Matrix3d information = Eigen::Matrix3d::Identity();  // prior cov^-1
  double gate = 0.0;

  double step_xy() const { return step_cells * resolution; }
  Pose2D pose(int i, int j, int t) const;
  // Squared Mahalanobis distance of lattice pose (i, j, t) from the mean.
  double distance2(int i, int j, int t) const;
  bool in_gate(int i, int j, int t) const;
  // Whether some (x, y) in the block of translations [i0, i1] x [j0, j1]
  // at heading t lies in the gate (the exact minimum of the Mahalanobis
  // distance over the block, with a hair of slack for rounding: a block
  // is only dropped when it surely holds no pose in the gate).
  bool block_meets_gate(int i0, int i1, int j0, int j1, int t) const;
  // Whether every (x, y) of the block lies in the gate, with a hair of
  // margin for rounding: the distance is convex, so its maximum over the
  // block is at a corner. Such a block's sub-blocks and poses need no test.
  bool block_inside_gate(int i0, int i1, int j0, int j1, int t) const;
  // The points' cells at heading t with the central translation.
  void cells(const std::vector<Point2D>& pts, int t, int* cx, int* cy) const;
};

// The lattice over the gate of `prior`: steps of step_xy (rounded to whole
// cells, at least one) and step_theta.
SearchLattice gate_lattice(const topology::PoseGaussian& prior, double gate, double step_xy,
                           double step_theta, double resolution);

// The level of the blocks bnb_modes starts from (its roots) with a stack of
// `levels` levels: as large as the stack allows, or as the window needs.
int root_level(const SearchLattice& lattice, int levels);

// How many roots bnb_modes bounds over `lattice`, at most: those of the
// gate's bounding box, at every heading, that put some point on the stack's
// map (the others cost the maximum with no bound computed).
int64_t roots_on_map(const CostStack& stack, const SearchLattice& lattice,
                     const std::vector<Point2D>& pts);

// `lattice` (from gate_lattice()), unless its roots would take more than
// `max_roots` of the search's budget of blocks: then its gate narrowed (the
// squared Mahalanobis radius by factors of 0.8, about the same mean) until
// they take no more. A prior far wider than the budget can search (a loop
// of a kilometre outdoors, composed over many arcs: 100-200 m and 0.6-0.8
// rad) is then searched exactly over its most probable part, instead of
// over the roots the search happens to bound first (those of the headings
// at the gate's edge) and no further. The same lattice poses keep the same
// indices; only the gate and the half-extents shrink.
SearchLattice budget_lattice(const CostStack& stack, const SearchLattice& lattice,
                             const std::vector<Point2D>& pts, int64_t max_roots);

struct SearchMode {
  int64_t cost = 0;  // sum of the points' costs (cost_stack.h), lower is better
  int i = 0, j = 0, t = 0;
  Pose2D pose;
};

struct ModeQuery {
  int count = 8;
  // Distinct modes: a pose within both distances (|dx|, |dy| < xy and
  // |dtheta| < theta) of a mode kept before is not another mode.
  double separation_xy = 0.3;
  double separation_theta = 0.1;
  int64_t max_cost = INT64_MAX;
  // ... nor costlier than the best mode by more than this.
  int64_t margin = INT64_MAX;
  // The search stops after bounding this many blocks, with the modes found
  // by then (exact up to there: each is the best of what was left when it
  // came out, but later ones may be missing). Bounds the time and memory
  // of a window where the bound cannot prune (a long look-alike corridor).
  int64_t max_blocks = INT64_MAX;
};

// What a branch and bound did (for tests and the cost report).
struct SearchStats {
  int64_t blocks = 0;  // blocks and poses whose bound was computed
  int64_t poses = 0;   // poses popped in cost order
  bool stopped = false;  // max_blocks was reached
};

// At most 100000 points and 32767 headings each side of the mean.
std::vector<SearchMode> bnb_modes(const CostStack& stack, const SearchLattice& lattice,
                                  const std::vector<Point2D>& pts, const ModeQuery& query,
                                  SearchStats* stats = nullptr);

// The reference: every pose of the lattice scored on the field itself.
// `window`: the matcher's coarse window, as given to the CostStack.
std::vector<SearchMode> exhaustive_modes(const MatchField& field, int window,
                                         const SearchLattice& lattice,
                                         const std::vector<Point2D>& pts,
                                         const ModeQuery& query);

}  // namespace hmt::tsbi

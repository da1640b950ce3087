// Classic point-to-point ICP of two 2D point sets, coarse to fine: the
// registration step of align_grids() (grid_alignment.h, step 2).
//
// Each iteration pairs every moving point (placed by the current pose) with
// its nearest fixed point if that is closer than
//   threshold + angular * |the moving point - the pose's position|
// (the angular term allows for the rotational error of the guess, which
// displaces far points more), then fits the rigid transform of the pairs in
// closed form (least squares, Arun / Horn in 2D). When the pose stops
// changing (every component within 1e-6) the threshold and its angular term
// are multiplied by `icp_threshold_decay`; the registration ends when the
// threshold falls below `icp_threshold_end`, when fewer than two points pair,
// or at `icp_max_iterations`: from then on the threshold decays every
// iteration until it is below the end, so that the result always comes from
// the fine pairing. This is the schedule of MRPT's CICP (icpClassic), with
// which it agrees to float precision (libs/alignment/tests/icp_vs_mrpt_test.cc).
//
// Deterministic: no random numbers or threads; the nearest-neighbour index is
// built from the points in their given order.
#pragma once

#include <vector>

#include "hmt/alignment/grid_alignment.h"
#include "hmt/common/pose2d.h"

namespace hmt::alignment {

struct IcpResult {
  Pose2D pose;         // of moving's frame in fixed's frame
  int iterations = 0;  // pairing + fit rounds
  int pairs = 0;       // pairs of the last round
};

// Uses the icp_* options. Empty point sets return `start` after no
// iteration.
IcpResult icp_register(const std::vector<Point2D>& moving,
                       const std::vector<Point2D>& fixed, const Pose2D& start,
                       const AlignmentOptions& opt);

}  // namespace hmt::alignment

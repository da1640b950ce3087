// A loop closure TSBI made on one hypothesis, waiting for TLCA: the robot
// left area `from` and was found in the known area `to`. It lives in the
// topological layer (not in libs/tlca, which fine-aligns it) because a saved
// run keeps each hypothesis's closures not yet accepted (hmt_map.bin), so a
// resumed run still fine-aligns them when their hypothesis wins.
#pragma once

#include <cstdint>
#include <optional>

#include "hmt/topology/hmt_map.h"

namespace hmt::topology {

struct ClosureRecord {
  AreaId from = kNoArea;
  AreaId to = kNoArea;
  uint64_t step = 0;
  // The arc between the two before this crossing, if they were adjacent.
  std::optional<Arc> arc_before;
  // TSBI's measurement: the pose of `to`'s frame in `from`'s frame.
  PoseGaussian measurement;
};

}  // namespace hmt::topology

// Offline grouping of a whole keyframe sequence (001 Sec. IV, steps 1-3):
// the SSO weight matrix of all keyframes (sparse, built with SsoGraph so that
// only pairs whose sensed regions can overlap are matched), then the
// recursive min-Ncut partition.
#pragma once

#include <vector>

#include "hmt/area/area_options.h"
#include "hmt/area/keyframe.h"
#include "hmt/area/ncut.h"
#include "hmt/area/partition.h"

namespace hmt::area {

struct Grouping {
  WeightMatrix W;  // row i = keyframes[i]
  // Groups of keyframe indices, sorted, ordered by their smallest index.
  std::vector<std::vector<int>> groups;
};

// window_size is ignored: every keyframe takes part.
Grouping group_keyframes(const std::vector<Keyframe>& keyframes,
                         const AreaOptions& options);

// W alone (the first step), for callers that partition it themselves.
WeightMatrix sso_weight_matrix(const std::vector<Keyframe>& keyframes,
                               const AreaOptions& options);

}  // namespace hmt::area

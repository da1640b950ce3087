#include "hmt/area/offline_grouping.h"

#include <numeric>

#include "hmt/area/sso_graph.h"

namespace hmt::area {

WeightMatrix sso_weight_matrix(const std::vector<Keyframe>& keyframes,
                               const AreaOptions& options) {
  SsoGraph graph(options);
  for (size_t i = 0; i < keyframes.size(); ++i)
    graph.add(static_cast<int>(i), keyframes[i]);
  std::vector<int> ids(keyframes.size());
  std::iota(ids.begin(), ids.end(), 0);
  return graph.weight_matrix(ids);
}

Grouping group_keyframes(const std::vector<Keyframe>& keyframes,
                         const AreaOptions& options) {
  Grouping g;
  g.W = sso_weight_matrix(keyframes, options);
  g.groups = recursive_partition(g.W, options.partition).groups;
  return g;
}

}  // namespace hmt::area

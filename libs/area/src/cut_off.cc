#include "hmt/area/cut_off.h"

#include "hmt/area/ncut.h"
#include "hmt/area/sso_graph.h"

namespace hmt::area {
namespace {

// How far above tau a partial Ncut must be to stop early: the whole
// graph's Ncut, summed in another order, cannot fall below it by rounding
// (its terms are SSO weights in [0, 1], a few thousand at most).
constexpr double kMargin = 1e-9;

// Twice the weight of the edges among the graph's keyframes: the sum of
// their degrees.
double degrees_sum(const SsoGraph& g) {
  const std::vector<int> ids = g.ids();
  return cut_values(g.weight_matrix(ids), std::vector<char>(ids.size(), 1)).assoc_a;
}

}  // namespace

bool cut_off(const std::vector<Keyframe>& keyframes, const std::vector<Keyframe>& latest,
             const AreaOptions& options, double tau,
             const std::shared_ptr<SsoPairCache>& keyframe_pairs, size_t* latest_matched) {
  if (latest_matched) *latest_matched = 0;
  if (keyframes.empty() || latest.empty()) return false;
  const int first_latest = static_cast<int>(keyframes.size());
  // The latest scans among themselves, into a cache of this call's own, so
  // that the whole graph below finds their pairs rather than matching them
  // again. Ids as in the whole graph: keyframes first.
  auto latest_pairs = std::make_shared<SsoPairCache>();
  SsoGraph among(options);
  among.use_pair_cache(latest_pairs);
  for (size_t j = 0; j < latest.size(); ++j)
    among.add(first_latest + static_cast<int>(j), latest[j]);
  const double latest_degrees = degrees_sum(among);
  // A cache is needed for the latest scans' lookups, so the keyframes get
  // keys through one of this call's own when none lasts.
  SsoGraph graph(options);
  graph.use_pair_cache(keyframe_pairs ? keyframe_pairs : std::make_shared<SsoPairCache>());
  for (size_t i = 0; i < keyframes.size(); ++i) graph.add(static_cast<int>(i), keyframes[i]);
  const double keyframe_degrees = degrees_sum(graph);
  graph.use_pair_cache(latest_pairs);
  std::vector<char> in_latest(keyframes.size(), 0);
  CutValues so_far;  // the cut by the latest scans added so far
  for (size_t j = 0; j < latest.size(); ++j) {
    const int id = first_latest + static_cast<int>(j);
    graph.add(id, latest[j]);
    for (int k = 0; k < first_latest; ++k) so_far.cut += graph.weight(id, k);
    in_latest.push_back(1);
    if (latest_matched) *latest_matched = j + 1;
    so_far.assoc_a = latest_degrees + so_far.cut;
    so_far.assoc_b = keyframe_degrees + so_far.cut;
    if (j + 1 < latest.size() && so_far.ncut() >= tau + kMargin) return false;
  }
  return normalized_cut(graph.weight_matrix(graph.ids()), in_latest) < tau;
}

}  // namespace hmt::area

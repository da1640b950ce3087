#include "hmt/topology/hypotheses.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace hmt::topology {

AreaId TopologicalHypothesis::current_area() const {
  if (path.empty())
    throw std::logic_error("TopologicalHypothesis: empty topological path");
  return path.back().area;
}

void enter_area(TopologicalHypothesis& h, AreaId area, uint64_t step) {
  if (area == kNoArea)
    throw std::invalid_argument("enter_area: kNoArea is not an area id");
  if (!h.path.empty()) {
    if (h.path.back().area == area)
      throw std::invalid_argument("enter_area: already in area " +
                                  std::to_string(area));
    if (step <= h.path.back().step)
      throw std::invalid_argument("enter_area: step " + std::to_string(step) +
                                  " is not after the last transition (step " +
                                  std::to_string(h.path.back().step) + ")");
  }
  h.path.push_back({area, step});
}

void validate(const TopologicalHypothesis& h, const HmtMap* map) {
  if (std::isnan(h.log_weight) ||
      h.log_weight == std::numeric_limits<double>::infinity())
    throw std::invalid_argument(
        "topological hypothesis: weight is NaN or +inf");
  if (h.path.empty())
    throw std::invalid_argument("topological hypothesis: empty path");
  for (size_t i = 0; i < h.path.size(); ++i) {
    const PathEntry& e = h.path[i];
    if (e.area == kNoArea)
      throw std::invalid_argument("topological hypothesis: entry " +
                                  std::to_string(i) + " has no area");
    if (map && !map->has_area(e.area))
      throw std::invalid_argument("topological hypothesis: entry " +
                                  std::to_string(i) + " names area " +
                                  std::to_string(e.area) +
                                  ", which the map does not have");
    if (i > 0 && e.area == h.path[i - 1].area)
      throw std::invalid_argument("topological hypothesis: entries " +
                                  std::to_string(i - 1) + " and " +
                                  std::to_string(i) + " are the same area");
    if (i > 0 && e.step <= h.path[i - 1].step)
      throw std::invalid_argument("topological hypothesis: entry " +
                                  std::to_string(i) +
                                  " does not come after the previous one");
  }
}

std::vector<double> normalized_weights(
    const std::vector<TopologicalHypothesis>& hypotheses) {
  if (hypotheses.empty())
    throw std::invalid_argument("normalized_weights: no hypotheses");
  double top = -std::numeric_limits<double>::infinity();
  for (const auto& h : hypotheses) {
    if (std::isnan(h.log_weight) ||
        h.log_weight == std::numeric_limits<double>::infinity())
      throw std::invalid_argument("normalized_weights: NaN or +inf weight");
    top = std::max(top, h.log_weight);
  }
  if (top == -std::numeric_limits<double>::infinity())
    throw std::invalid_argument("normalized_weights: every weight is zero");
  std::vector<double> w;
  w.reserve(hypotheses.size());
  double sum = 0.0;
  for (const auto& h : hypotheses) {
    w.push_back(std::exp(h.log_weight - top));  // exp(-inf) = 0
    sum += w.back();
  }
  for (double& x : w) x /= sum;
  return w;
}

std::map<AreaId, double> position_pmf(
    const std::vector<TopologicalHypothesis>& hypotheses) {
  const std::vector<double> w = normalized_weights(hypotheses);
  std::map<AreaId, double> pmf;
  for (size_t k = 0; k < hypotheses.size(); ++k)
    pmf[hypotheses[k].current_area()] += w[k];
  return pmf;
}

std::vector<TopologyProbability> path_pmf(
    const std::vector<TopologicalHypothesis>& hypotheses) {
  const std::vector<double> w = normalized_weights(hypotheses);
  std::map<std::vector<AreaId>, double> by_path;
  for (size_t k = 0; k < hypotheses.size(); ++k) {
    std::vector<AreaId> areas;
    areas.reserve(hypotheses[k].path.size());
    for (const auto& e : hypotheses[k].path) areas.push_back(e.area);
    by_path[std::move(areas)] += w[k];
  }
  std::vector<TopologyProbability> out;
  out.reserve(by_path.size());
  for (auto& kv : by_path) out.push_back({kv.first, kv.second});
  // by_path is in lexicographic order; a stable sort keeps it among ties.
  std::stable_sort(
      out.begin(), out.end(),
      [](const TopologyProbability& a, const TopologyProbability& b) {
        return a.probability > b.probability;
      });
  return out;
}

std::vector<PathEntry> common_prefix(
    const std::vector<TopologicalHypothesis>& hypotheses) {
  if (hypotheses.empty()) return {};
  size_t n = hypotheses.front().path.size();
  const auto& first = hypotheses.front().path;
  for (const auto& h : hypotheses) {
    n = std::min(n, h.path.size());
    size_t i = 0;
    while (i < n && h.path[i] == first[i]) ++i;
    n = i;
  }
  return {first.begin(), first.begin() + static_cast<std::ptrdiff_t>(n)};
}

size_t forget_common_history(std::vector<TopologicalHypothesis>& hypotheses) {
  if (hypotheses.empty()) return 0;
  size_t drop = common_prefix(hypotheses).size();
  for (const auto& h : hypotheses)
    drop = std::min(drop, h.path.empty() ? 0 : h.path.size() - 1);
  if (drop == 0) return 0;
  for (auto& h : hypotheses)
    h.path.erase(h.path.begin(),
                 h.path.begin() + static_cast<std::ptrdiff_t>(drop));
  return drop;
}

}  // namespace hmt::topology

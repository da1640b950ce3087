// Topological hypotheses: each particle of the HMT-SLAM filter carries its
// own topological path gamma^t -- the sequence of areas it has traversed and
// when it entered each -- and so its own hypothesis about the map's topology
// (002 Fig. 4: the same sequence of traversed areas read as "all distinct"
// or as "area 4 is area 0 again"). Particles descend from common ancestors,
// so their paths typically share a prefix and differ only in the recent past.
//
// Eq. 14 (as read here; the OCR garbles the sub/superscripts):
//     P(gamma_t = gamma | u^t, o^t) = sum_{k in Omega} w^[k],
//     Omega = {k : gamma_t^[k] = gamma}
// the marginal PMF of the topological position is the sum of the normalised
// weights of the particles whose current area is gamma (position_pmf). The
// text around it speaks of "the PMF of the topological path ... for
// visualizing the topological structure hypotheses" and evaluates it "for
// each desired value of gamma^t" (Fig. 10): the same marginalisation keyed by
// the whole sequence of areas, which is path_pmf.
//
// Section IV-D: hypotheses about the whole topological path "can be
// forgotten until the point where the differences between particles begin":
// common_prefix() is that shared history, forget_common_history() drops it
// (keeping each path's current entry, so the position is never lost).
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include "hmt/topology/hmt_map.h"

namespace hmt::topology {

// The robot entered `area` at log step `step` (and stayed there until the
// next entry's step).
struct PathEntry {
  AreaId area = 0;
  uint64_t step = 0;
  bool operator==(const PathEntry& o) const {
    return area == o.area && step == o.step;
  }
  bool operator!=(const PathEntry& o) const { return !(*this == o); }
};

struct TopologicalHypothesis {
  // Non-empty; steps strictly increasing; consecutive areas differ (a
  // transition always goes to another area: a new one or a loop closure).
  std::vector<PathEntry> path;
  // Unnormalised log of the particle weight (as GridRbpf keeps it); -inf is
  // allowed (a weight of zero), NaN is not.
  double log_weight = 0.0;

  // Throws std::logic_error on an empty path.
  AreaId current_area() const;
};

// Appends the transition "entered `area` at `step`". Throws
// std::invalid_argument if it breaks the invariants above.
void enter_area(TopologicalHypothesis& h, AreaId area, uint64_t step);

// Throws std::invalid_argument naming the broken invariant; with a map, also
// if a path names an area the map does not have.
void validate(const TopologicalHypothesis& h, const HmtMap* map = nullptr);

// exp(log_weight) normalised to sum 1 (computed stably, relative to the
// largest). Throws std::invalid_argument for an empty set, a NaN or +inf
// weight, or all weights zero.
std::vector<double> normalized_weights(
    const std::vector<TopologicalHypothesis>& hypotheses);

// Eq. 14: probability of each current area (only areas with a particle).
std::map<AreaId, double> position_pmf(
    const std::vector<TopologicalHypothesis>& hypotheses);

// The PMF over topologies: probability of each distinct sequence of areas
// (entry steps ignored: they say when, not what, the topology is), most
// probable first, ties in lexicographic order of the sequence.
struct TopologyProbability {
  std::vector<AreaId> areas;
  double probability = 0.0;
};
std::vector<TopologyProbability> path_pmf(
    const std::vector<TopologicalHypothesis>& hypotheses);

// The longest prefix (areas and steps) that every path shares; empty for no
// hypotheses.
std::vector<PathEntry> common_prefix(
    const std::vector<TopologicalHypothesis>& hypotheses);

// Section IV-D: removes the common prefix from every path, except that each
// path keeps at least its last entry. Returns the number of entries removed
// from each path.
size_t forget_common_history(std::vector<TopologicalHypothesis>& hypotheses);

}  // namespace hmt::topology

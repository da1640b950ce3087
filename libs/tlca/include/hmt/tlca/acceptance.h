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
// When is a hypothesis "highly dominant (or unique)"? Two policies:
//  - kProbability: its probability reaches accept_probability; the others
//    are dropped.
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
  alignment::AlignmentOptions alignment;
  // Reads [tlca] (policy = probability | unique, accept_probability,
  // fine_alignment) and the alignment's own section ([alignment]).
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
  std::string reason;          // why not, otherwise
  topology::PoseGaussian used; // the measurement fused into the arc
  double correction_m = 0.0;   // how far alignment moved `to`'s origin
  double correction_rad = 0.0;
};

// The two halves of accept_closure, so the costly one can run on its own
// thread (the framework's TLCA process) over a snapshot of the map:
// align_closure fine-aligns the two areas' archived grids (when both exist
// and the option is on) and says which measurement to use (the aligned one,
// or TSBI's when alignment failed); apply_closure rewrites the arc from..to
// as arc_before (+) that measurement.
ClosureReport align_closure(const topology::HmtMap& map, const ClosureRecord& closure,
                            const TlcaOptions& options);
void apply_closure(topology::HmtMap& map, const ClosureReport& report);

// align_closure then apply_closure on the same map.
ClosureReport accept_closure(topology::HmtMap& map, const ClosureRecord& closure,
                             const TlcaOptions& options);

}  // namespace hmt::tlca

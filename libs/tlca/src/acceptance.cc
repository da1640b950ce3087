#include "hmt/tlca/acceptance.h"

#include <cmath>

namespace hmt::tlca {

using topology::PoseGaussian;

void TlcaOptions::load(Config& cfg, const std::string& s) {
  const std::string p = cfg.get_string(s, "policy", "probability");
  accept_probability = cfg.get_double(s, "accept_probability", accept_probability);
  fine_alignment = cfg.get_bool(s, "fine_alignment", fine_alignment);
  require(p == "probability" || p == "unique", s, "policy", "'probability' or 'unique'");
  policy = p == "probability" ? AcceptancePolicy::kProbability : AcceptancePolicy::kUnique;
  require(accept_probability > 0.5 && accept_probability <= 1.0, s,
          "accept_probability", "in (0.5, 1]");
  alignment.load(cfg);
}

std::optional<size_t> dominant(const std::vector<double>& probabilities,
                               const TlcaOptions& options) {
  if (probabilities.size() == 1) return 0;
  if (probabilities.empty() || options.policy == AcceptancePolicy::kUnique)
    return std::nullopt;
  size_t best = 0;
  for (size_t i = 1; i < probabilities.size(); ++i)
    if (probabilities[i] > probabilities[best]) best = i;
  if (probabilities[best] >= options.accept_probability) return best;
  return std::nullopt;
}

ClosureReport align_closure(const topology::HmtMap& map, const ClosureRecord& closure,
                            const TlcaOptions& options) {
  ClosureReport report;
  report.record = closure;
  report.used = closure.measurement;
  const auto& from_map = map.area(closure.from).map;
  const auto& to_map = map.area(closure.to).map;
  if (!options.fine_alignment) {
    report.reason = "fine alignment disabled";
  } else if (!from_map || !to_map) {
    report.reason = "an area has no archived map";
  } else {
    // Register `from`'s grid (moving) in `to`'s frame (fixed): the initial
    // guess is `from`'s frame seen from `to`, the inverse of the measurement.
    const alignment::AlignmentResult r = alignment::align_grids(
        *from_map, *to_map, topology::inverse(closure.measurement), options.alignment);
    if (r.ok) {
      report.aligned = true;
      report.used = topology::inverse(r.pose);
      const Pose2D d = report.used.mean - closure.measurement.mean;
      report.correction_m = d.norm();
      report.correction_rad = std::fabs(d.theta);
    } else {
      report.reason = r.reason;
    }
  }
  return report;
}

void apply_closure(topology::HmtMap& map, const ClosureReport& report) {
  const ClosureRecord& closure = report.record;
  topology::Arc arc;
  arc.from = closure.from;
  arc.to = closure.to;
  arc.pose = report.used;
  arc.measurements = 1;
  if (closure.arc_before) {
    // The stored arc may be in either direction; fuse in from -> to.
    const topology::Arc& b = *closure.arc_before;
    const PoseGaussian before =
        b.from == closure.from ? b.pose : topology::inverse(b.pose);
    arc.pose = topology::fuse(before, report.used);
    arc.measurements = b.measurements + 1;
  }
  map.set_arc(arc);
}

ClosureReport accept_closure(topology::HmtMap& map, const ClosureRecord& closure,
                             const TlcaOptions& options) {
  ClosureReport report = align_closure(map, closure, options);
  apply_closure(map, report);
  return report;
}

}  // namespace hmt::tlca

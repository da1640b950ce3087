#include "hmt/tlca/acceptance.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "hmt/topology/shortest_paths.h"

namespace hmt::tlca {

using topology::PoseGaussian;

namespace {

std::string format(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

void add_reason(ClosureReport& report, const std::string& why) {
  report.reason += (report.reason.empty() ? "" : "; ") + why;
}

// The map's arcs but the closure's, with what that arc held before this
// crossing (if anything): the map in which the closure's loop is checked,
// with the floor added to every loop arc (every arc but an area's creating
// arc), as the robust global estimate's test does. Only the graph matters
// to Dijkstra, so the areas are bare.
topology::HmtMap without_closure(const topology::HmtMap& map, const ClosureRecord& closure,
                                 const Eigen::Matrix3d& floor) {
  topology::HmtMap graph;
  for (const topology::AreaId id : map.area_ids()) graph.add_area(id);
  auto add = [&](topology::Arc arc) {
    if (map.area(arc.to).frame.parent != arc.from && map.area(arc.from).frame.parent != arc.to)
      arc.pose.cov += floor;
    graph.set_arc(arc);
  };
  const std::pair<topology::AreaId, topology::AreaId> closure_pair(
      std::min(closure.from, closure.to), std::max(closure.from, closure.to));
  for (const auto& [ends, arc] : map.arcs())
    if (ends != closure_pair) add(arc);
  if (closure.arc_before) add(*closure.arc_before);
  return graph;
}

// (b) of the header: the other path from `from` to `to`, and the closure's
// measurement against it; an inconsistent measurement is inflated.
void check_loop(const topology::HmtMap& map, const ClosureRecord& closure,
                const TlcaOptions& options, ClosureReport& report) {
  const double fxy = options.consistency_floor_xy * options.consistency_floor_xy;
  const double fth = options.consistency_floor_theta * options.consistency_floor_theta;
  const Eigen::Matrix3d floor = Eigen::Vector3d(fxy, fxy, fth).asDiagonal();
  const topology::PathTree tree =
      topology::shortest_paths(without_closure(map, closure, floor), closure.from);
  if (!tree.reaches(closure.to)) {  // a bridge: no loop to check or bend
    if (!report.consistent) add_reason(report, "fused as measured: it closes no loop");
    return;
  }
  const topology::PathTree::Node& node = tree.nodes.at(closure.to);
  report.loop_hops = node.hops;
  const Eigen::Vector3d d = topology::difference(report.used.mean, node.pose.mean);
  const Eigen::Matrix3d S = report.used.cov + node.pose.cov + floor;
  report.loop_chi2 = d.dot(S.ldlt().solve(d));
  const bool loop_ok = report.loop_chi2 <= options.consistency_chi2;
  if (!loop_ok) {
    report.consistent = false;
    add_reason(report, "inconsistent with the other path of " + std::to_string(node.hops) +
                           " arcs: off by (" + format(d(0)) + " m, " + format(d(1)) + " m, " +
                           format(d(2)) + " rad), squared Mahalanobis distance " +
                           format(report.loop_chi2) + " above " +
                           format(options.consistency_chi2));
  }
  if (!report.consistent) {
    report.used.cov = S + d * d.transpose();
    add_reason(report, "fused with its covariance inflated");
  }
}

}  // namespace

void TlcaOptions::load(Config& cfg, const std::string& s) {
  const std::string p = cfg.get_string(s, "policy", "probability");
  accept_probability = cfg.get_double(s, "accept_probability", accept_probability);
  fine_alignment = cfg.get_bool(s, "fine_alignment", fine_alignment);
  consistency_check = cfg.get_bool(s, "consistency_check", consistency_check);
  consistency_chi2 = cfg.get_double(s, "consistency_chi2", consistency_chi2);
  consistency_floor_xy = cfg.get_double(s, "consistency_floor_xy", consistency_floor_xy);
  consistency_floor_theta = cfg.get_double(s, "consistency_floor_theta", consistency_floor_theta);
  require(consistency_chi2 > 0.0 && std::isfinite(consistency_chi2), s, "consistency_chi2",
          "positive and finite");
  require(consistency_floor_xy >= 0.0 && std::isfinite(consistency_floor_xy), s,
          "consistency_floor_xy", ">= 0 and finite");
  require(consistency_floor_theta >= 0.0 && std::isfinite(consistency_floor_theta), s,
          "consistency_floor_theta", ">= 0 and finite");
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
    report.inlier_ratio = r.inlier_ratio;
    report.overlap_points = r.overlap_points;
    if (r.ok) {
      report.aligned = true;
      report.used = topology::inverse(r.pose);
      const Pose2D d = report.used.mean - closure.measurement.mean;
      report.correction_m = d.norm();
      report.correction_rad = std::fabs(d.theta);
    } else {
      report.reason = r.reason;
    }
    // (a): the alignment ran on enough points of both grids and found
    // them apart where the closure puts them.
    const int min_points = options.alignment.min_points;
    if (options.consistency_check && r.moving_points >= min_points &&
        r.fixed_points >= min_points && r.overlap_points >= min_points &&
        r.inlier_ratio < options.alignment.min_inlier_ratio) {
      report.consistent = false;
      add_reason(report, "the grids do not overlap at the closure: inlier ratio " +
                             format(r.inlier_ratio) + " below " +
                             format(options.alignment.min_inlier_ratio));
    }
  }
  if (options.consistency_check) check_loop(map, closure, options, report);
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

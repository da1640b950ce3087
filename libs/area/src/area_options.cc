#include "hmt/area/area_options.h"

#include <cmath>

#include "hmt/common/config.h"
#include "hmt/common/error.h"

namespace hmt::area {

SplitMethod parse_split_method(const std::string& text,
                               const std::string& section,
                               const std::string& key) {
  if (text == "mean") return SplitMethod::kMean;
  if (text == "sign") return SplitMethod::kSign;
  if (text == "sweep") return SplitMethod::kSweep;
  throw ConfigError("[" + section + "] " + key + " = '" + text +
                    "': must be one of mean, sign, sweep");
}

const char* to_string(SplitMethod m) {
  switch (m) {
    case SplitMethod::kMean:
      return "mean";
    case SplitMethod::kSign:
      return "sign";
    case SplitMethod::kSweep:
      return "sweep";
  }
  return "mean";
}

void AreaOptions::load(Config& cfg, const std::string& s) {
  sso.delta = cfg.get_double(s, "delta", sso.delta);
  sso.use_probabilistic =
      cfg.get_bool(s, "use_probabilistic", sso.use_probabilistic);
  sso.beta = cfg.get_double(s, "beta", sso.beta);
  sso.range_std = cfg.get_double(s, "range_std", sso.range_std);
  sso.bearing_std = cfg.get_double(s, "bearing_std", sso.bearing_std);
  sso.gate = cfg.get_double(s, "gate", sso.gate);
  sso.descriptor_threshold =
      cfg.get_double(s, "descriptor_threshold", sso.descriptor_threshold);
  // tau: a number, or "auto" (derived from the sensor, area_size.h).
  cfg.get_double_or_auto(s, "tau", &partition.tau, &partition.tau_from_sensor);
  partition.min_cluster_size =
      cfg.get_int(s, "min_cluster_size", partition.min_cluster_size);
  partition.split_method = parse_split_method(
      cfg.get_string(s, "split_method", to_string(partition.split_method)), s,
      "split_method");
  min_sso = cfg.get_double(s, "min_sso", min_sso);
  window_size = cfg.get_int(s, "window_size", window_size);
  index_cell_size = cfg.get_double(s, "index_cell_size", index_cell_size);
  threads = cfg.get_int(s, "threads", threads);
  PlacementOptions& p = placement;
  p.policy = parse_placement(cfg.get_string(s, "placement", to_string(p.policy)), s, "placement");
  p.e_min = cfg.get_double(s, "placement_e_min", p.e_min);
  p.threshold = cfg.get_double(s, "placement_threshold", p.threshold);
  p.decay = cfg.get_double(s, "placement_decay", p.decay);
  p.cutoff = cfg.get_double(s, "placement_cutoff", p.cutoff);
  p.rate = cfg.get_double(s, "placement_rate", p.rate);
  p.normal_radius = cfg.get_double(s, "placement_normal_radius", p.normal_radius);
  p.reference_window = cfg.get_double(s, "placement_reference_window", p.reference_window);
  p.max_range = cfg.get_double(s, "placement_max_range", p.max_range);
  validate(s);
}

void AreaOptions::validate(const std::string& s) const {
  require(sso.delta > 0.0, s, "delta", "> 0 (metres)");
  require(sso.beta >= 0.0 && sso.beta < 1.0, s, "beta",
          "in [0, 1) radians (0: the scan's own angular step)");
  require(sso.range_std >= 0.0, s, "range_std", ">= 0 (metres)");
  require(sso.bearing_std >= 0.0, s, "bearing_std", ">= 0 (radians)");
  require(sso.gate > 0.0, s, "gate",
          "> 0 (a chi-square threshold on the squared Mahalanobis distance)");
  require(sso.descriptor_threshold >= 0.0, s, "descriptor_threshold",
          ">= 0 (0 ignores descriptors)");
  require(partition.tau >= 0.0 && partition.tau <= 2.0, s, "tau",
          "in [0, 2] (the range of the normalized cut)");
  require(partition.min_cluster_size >= 1, s, "min_cluster_size", ">= 1");
  require(min_sso >= 0.0 && min_sso < 1.0, s, "min_sso", "in [0, 1)");
  require(window_size >= 2, s, "window_size", ">= 2");
  require(index_cell_size > 0.0, s, "index_cell_size", "> 0 (metres)");
  require(threads >= 0 && threads <= 1024, s, "threads", "in [0, 1024] (0 = one per core)");
  const PlacementOptions& p = placement;
  require(p.e_min > 0.0, s, "placement_e_min", "> 0 (metres)");
  require(p.threshold > 0.0, s, "placement_threshold", "> 0");
  require(p.decay >= 0.0, s, "placement_decay", ">= 0 (1/m)");
  require(p.cutoff > 0.0, s, "placement_cutoff", "> 0");
  require(p.rate > 0.0, s, "placement_rate", "> 0");
  require(p.normal_radius > 0.0, s, "placement_normal_radius", "> 0 (metres)");
  require(p.reference_window > 0.0 && p.reference_window < 180.0, s,
          "placement_reference_window", "in (0, 180) degrees");
  require(p.max_range > 0.0, s, "placement_max_range", "> 0 (metres)");
}

}  // namespace hmt::area

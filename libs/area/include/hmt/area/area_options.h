// Options of the area abstraction: sensed-space overlap (SSO), spectral
// partition and the online keyframe graph, all read from one INI section.
//
// Every option is read through hmt::Config (so a typo in the INI file is an
// error, see config.h) and validated with hmt::require.
#pragma once

#include <string>

#include "hmt/area/placement.h"

namespace hmt {
class Config;
}

namespace hmt::area {

// How the bisection threshold is chosen on the Fiedler vector (000 Sec. 2.2).
enum class SplitMethod {
  kMean,   // threshold = mean of the components (the papers' choice)
  kSign,   // threshold = 0
  kSweep,  // every threshold between sorted components; keep the least Ncut
};

// "mean" / "sign" / "sweep"; throws ConfigError naming section and key
// otherwise.
SplitMethod parse_split_method(const std::string& text,
                               const std::string& section,
                               const std::string& key);
const char* to_string(SplitMethod m);

struct SsoOptions {
  // Point-match tolerance delta [m] (001 Eq. 16): a point of one scan is
  // matched if a point of the other scan lies within delta.
  double delta = 0.20;
  // Use the Mahalanobis test of 000 Eq. 16 instead of the fixed delta (the
  // default: its tolerance follows the beam spacing, see area_size.h).
  bool use_probabilistic = true;
  // Sampling term sigma_f = r * beta [rad] (000 Eq. 16). 0 takes each scan's
  // own angular step, which is what the paper suggests ("of the order of the
  // discrete angular steps").
  double beta = 0.0;
  // Sensor noise of a range-bearing reading (the Sigma_s of 000 Eq. 16).
  double range_std = 0.01;   // [m]
  double bearing_std = 0.0;  // [rad]
  // Gate on the squared Mahalanobis distance: chi-square with 2 degrees of
  // freedom; 9.21 is its 99% quantile (000 uses "below 3", i.e. d^2 < 9).
  double gate = 9.21;
  // Landmarks with descriptors on both sides also need a Euclidean descriptor
  // distance <= this to match; <= 0 ignores descriptors.
  double descriptor_threshold = 0.0;
};

struct PartitionOptions {
  // A bisection is accepted while its Ncut < tau (000 Table 1). tau = 1 is the
  // parameter-free choice of 001 Eq. 12-13; tau = 0 never splits. 0.5 is
  // what the rule of area_size.h gives a 180 degree laser.
  double tau = 0.5;
  // `tau = auto` in the configuration (the default): tau is derived from the
  // sensor's field of view when the log is read (area_size.h, resolve_tau).
  bool tau_from_sensor = true;
  // Neither side of an accepted bisection may have fewer nodes.
  int min_cluster_size = 1;
  SplitMethod split_method = SplitMethod::kMean;
};

struct AreaOptions {
  SsoOptions sso;
  PartitionOptions partition;
  // Edges with a smaller SSO are not stored, which keeps the weight matrix
  // sparse (an SSO this small carries no real overlap).
  double min_sso = 1e-3;
  // Online: at most this many of the current area's most recent keyframes
  // take part in the graph (bounds the cost per keyframe).
  int window_size = 300;
  // Cell size [m] of the coarse spatial hash of keyframe bounding boxes used
  // to find the keyframes whose sensed regions can overlap (probabilistic
  // SSO; the fixed-delta SSO uses a finer point index, see sso_graph.h).
  double index_cell_size = 4.0;
  // Worker threads for a new keyframe's probabilistic SSO pairs (0 = one per
  // core). The pairs are independent and joined in order: results do not
  // depend on it.
  int threads = 0;
  // Which rule starts a new area (placement.h): keys placement,
  // placement_e_min, placement_threshold, placement_decay, placement_cutoff,
  // placement_rate, placement_normal_radius, placement_reference_window,
  // placement_max_range.
  PlacementOptions placement;

  // Reads every option from `section` (keys: delta, use_probabilistic, beta,
  // range_std, bearing_std, gate, descriptor_threshold, tau,
  // min_cluster_size, split_method, min_sso, window_size, index_cell_size,
  // threads),
  // keeping the current values as defaults, then validates.
  void load(Config& cfg, const std::string& section = "area");
  // Throws ConfigError for the first out-of-range value.
  void validate(const std::string& section = "area") const;
};

}  // namespace hmt::area

#include "hmt/metric_slam/rbpf_options.h"

#include <cmath>

#include <string>

namespace hmt::metric_slam {

void RbpfOptions::load(Config& cfg) {
  const std::string s = "metric_slam";
  particles = cfg.get_int(s, "particles", particles);
  const int seed_i = cfg.get_int(s, "seed", static_cast<int>(seed));
  threads = cfg.get_int(s, "threads", threads);
  const std::string prop = cfg.get_string(s, "proposal", "optimal");
  resample_threshold = cfg.get_double(s, "resample_threshold", resample_threshold);
  update_distance = cfg.get_double(s, "update_distance", update_distance);
  update_angle = cfg.get_double(s, "update_angle", update_angle);
  map_update_distance = cfg.get_double(s, "map_update_distance", map_update_distance);
  map_update_angle = cfg.get_double(s, "map_update_angle", map_update_angle);
  likelihood_gain = cfg.get_double(s, "likelihood_gain", likelihood_gain);
  proposal_gain = cfg.get_double(s, "proposal_gain", proposal_gain);
  sample_linear = cfg.get_double(s, "sample_linear", sample_linear);
  sample_angular = cfg.get_double(s, "sample_angular", sample_angular);
  lattice_beams = cfg.get_int(s, "lattice_beams", lattice_beams);
  heading_search_ratio = cfg.get_double(s, "heading_search_ratio", heading_search_ratio);
  heading_search_range = cfg.get_double(s, "heading_search_range", heading_search_range);
  require(particles >= 1 && particles <= 100000, s, "particles", "in [1, 100000]");
  require(seed_i >= 0, s, "seed", ">= 0");
  seed = static_cast<uint64_t>(seed_i);
  require(threads >= 0 && threads <= 256, s, "threads", "in [0, 256]");
  require(prop == "optimal" || prop == "odometry", s, "proposal",
          "'optimal' or 'odometry'");
  proposal = prop == "optimal" ? ProposalKind::kOptimal : ProposalKind::kOdometry;
  require(resample_threshold >= 0 && resample_threshold <= 1, s,
          "resample_threshold", "in [0, 1]");
  require(update_distance >= 0, s, "update_distance", ">= 0");
  require(update_angle >= 0, s, "update_angle", ">= 0");
  require(map_update_distance >= 0, s, "map_update_distance", ">= 0");
  require(map_update_angle >= 0, s, "map_update_angle", ">= 0");
  require(likelihood_gain >= 1, s, "likelihood_gain", ">= 1");
  require(proposal_gain >= 1, s, "proposal_gain", ">= 1");
  require(sample_linear > 0, s, "sample_linear", "> 0");
  require(sample_angular > 0, s, "sample_angular", "> 0");
  require(lattice_beams >= 0, s, "lattice_beams", ">= 0 (0: all beams)");
  require(heading_search_ratio >= 0 && heading_search_ratio <= 1, s, "heading_search_ratio",
          "in [0, 1] (0: off)");
  require(heading_search_range >= 0 && heading_search_range <= M_PI, s, "heading_search_range",
          "in [0, pi] (0: off)");

  resolution = cfg.get_double("grid", "resolution", resolution);
  require(resolution >= 0.005 && resolution <= 1.0, "grid", "resolution",
          "in [0.005, 1] metres");
  insertion.load(cfg, "grid");
  matcher.load(cfg, "scan_matcher");
  if (insertion.range_from_matcher) insertion.max_range = matcher.max_range;
  // Log-odds are clamped at p_clamp: a threshold at or above it is never
  // reached, and every scan would fall back to odometry.
  require(matcher.occupied_probability < insertion.p_clamp, "scan_matcher",
          "occupied_probability", "below [grid] p_clamp (" + std::to_string(insertion.p_clamp) +
                                      "), which no cell exceeds");
  motion.load(cfg, "motion_model");
}

}  // namespace hmt::metric_slam

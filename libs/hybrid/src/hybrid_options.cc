#include "hmt/hybrid/hybrid_options.h"

#include <algorithm>

namespace hmt::hybrid {

void HybridOptions::load(Config& cfg, const std::string& s) {
  max_hypotheses = cfg.get_int(s, "max_hypotheses", max_hypotheses);
  prune_probability = cfg.get_double(s, "prune_probability", prune_probability);
  min_particles = cfg.get_int(s, "min_particles", min_particles);
  event_evidence = cfg.get_bool(s, "event_evidence", event_evidence);
  end_of_log_event = cfg.get_bool(s, "end_of_log_event", end_of_log_event);
  keyframe_distance = cfg.get_double(s, "keyframe_distance", keyframe_distance);
  keyframe_angle = cfg.get_double(s, "keyframe_angle", keyframe_angle);
  arc_std_xy = cfg.get_double(s, "arc_std_xy", arc_std_xy);
  arc_std_theta = cfg.get_double(s, "arc_std_theta", arc_std_theta);
  arc_std_xy_per_metre = cfg.get_double(s, "arc_std_xy_per_metre", arc_std_xy_per_metre);
  arc_std_theta_per_metre =
      cfg.get_double(s, "arc_std_theta_per_metre", arc_std_theta_per_metre);
  arc_std_theta_max = cfg.get_double(s, "arc_std_theta_max", arc_std_theta_max);
  require(max_hypotheses >= 1 && max_hypotheses <= 64, s, "max_hypotheses", "in [1, 64]");
  require(prune_probability >= 0 && prune_probability < 0.5, s, "prune_probability",
          "in [0, 0.5)");
  require(min_particles >= 0, s, "min_particles", ">= 0");
  require(keyframe_distance > 0, s, "keyframe_distance", "> 0");
  require(keyframe_angle > 0, s, "keyframe_angle", "> 0");
  require(arc_std_xy > 0, s, "arc_std_xy", "> 0");
  require(arc_std_theta > 0, s, "arc_std_theta", "> 0");
  require(arc_std_xy_per_metre >= 0, s, "arc_std_xy_per_metre", ">= 0");
  require(arc_std_theta_per_metre >= 0, s, "arc_std_theta_per_metre", ">= 0");
  require(arc_std_theta_max >= 0, s, "arc_std_theta_max", ">= 0 (0: no cap)");
}

double HybridOptions::arc_floor_theta(double metres) const {
  const double grown = arc_std_theta + arc_std_theta_per_metre * metres;
  // The cap bounds the growth only: never below the constant part.
  return arc_std_theta_max > 0 ? std::max(arc_std_theta, std::min(grown, arc_std_theta_max))
                               : grown;
}

}  // namespace hmt::hybrid

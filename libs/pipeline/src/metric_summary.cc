#include "hmt/pipeline/metric_summary.h"

#include <cstdio>

namespace hmt::pipeline {

nlohmann::json metric_summary(const metric_slam::RbpfStats& s) {
  const double moves = static_cast<double>(s.particle_moves);
  return {{"scans_filtered", s.steps - s.skipped_steps},
          {"resamplings", s.resamplings},
          {"particle_moves", s.particle_moves},
          {"odometry_fallbacks", s.odometry_fallbacks},
          {"shared_starts", s.shared_starts},
          {"odometry_fallback_fraction",
           moves > 0 ? static_cast<double>(s.odometry_fallbacks) / moves : 0.0}};
}

void warn_if_scans_did_not_match(const nlohmann::json& summary) {
  const double f = summary.at("odometry_fallback_fraction").get<double>();
  if (!(f > 0.5)) return;
  std::fprintf(stderr,
               "hmt-slam: warning: at %.0f%% of the particles' steps the scan matched no "
               "map and the odometry alone moved them; check [scan_matcher] max_range, "
               "the laser's pose and the log's ranges\n",
               100.0 * f);
}

}  // namespace hmt::pipeline

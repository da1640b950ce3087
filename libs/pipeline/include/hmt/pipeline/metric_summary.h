// What a metric filter did over a log, as summary.json says it: shared by
// `hmt-slam run` (under "metric_slam", for the most probable hypothesis) and
// `hmt-slam metric` (at the top level), so both count alike and both warn
// when the scans did not match.
#pragma once

#include <nlohmann/json.hpp>

#include "hmt/metric_slam/grid_rbpf.h"

namespace hmt::pipeline {

// scans_filtered, resamplings, particle_moves, odometry_fallbacks,
// shared_starts and odometry_fallback_fraction (fallbacks / moves; 0 with
// no moves).
nlohmann::json metric_summary(const metric_slam::RbpfStats& s);

// Most particle-steps moved by the odometry alone (fraction above one
// half): the map is the odometry's, whatever the outputs look like. Said on
// stderr, naming what to check, rather than left in the summary.
void warn_if_scans_did_not_match(const nlohmann::json& summary);

}  // namespace hmt::pipeline

// Writers of the HMT job's text outputs (all atomic: a failed write never
// leaves a half file).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "hmt/global_map/global_poses.h"
#include "hmt/hybrid/hybrid_filter.h"
#include "hmt/topology/hmt_map.h"

namespace hmt::pipeline {

// One row per step and area with a particle there: step,time,area,probability.
struct PmfRow {
  uint64_t step;
  double time;
  topology::AreaId area;
  double probability;
};
void write_pmf_csv(const std::string& path, const std::vector<PmfRow>& rows);

void write_tsbi_events_csv(const std::string& path,
                           const std::vector<hybrid::TransitionEvent>& events);

// Areas with their global poses and covariances, arcs with mean, covariance
// and the number of fused measurements.
void write_topology_json(const std::string& path, const topology::HmtMap& map,
                         const global_map::GlobalPoses& poses);
void write_topology_dot(const std::string& path, const topology::HmtMap& map);

}  // namespace hmt::pipeline

// Writers of the HMT job's text outputs (all atomic: a failed write never
// leaves a half file).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "hmt/framework/hmt_system.h"
#include "hmt/global_map/global_poses.h"
#include "hmt/hybrid/hybrid_filter.h"
#include "hmt/topology/hmt_map.h"

namespace hmt::pipeline {

// From metric SLAM's trace of every step (framework::StepTrace):
//  topological_pmf.csv  step,time,area,probability (002 Eq. 14, Fig. 10)
//  ess.csv              step,time,hypothesis,probability,area,ess,particles
//  memory.csv           step,time,peak_rss_mb,map_memory_mb,hypotheses,areas
//                       (the sampled steps; Fig. 9e)
void write_pmf_csv(const std::string& path, const std::vector<framework::StepTrace>& traces);
void write_ess_csv(const std::string& path, const std::vector<framework::StepTrace>& traces);
void write_memory_csv(const std::string& path, const std::vector<framework::StepTrace>& traces);
// process_times.csv: step,time,metric_slam_ms,aam_ms,tsbi_ms,tlca_ms (Fig. 9c).
void write_process_times_csv(const std::string& path, const framework::ProcessTimes& times,
                             const std::vector<framework::StepTrace>& traces);

void write_tsbi_events_csv(const std::string& path,
                           const std::vector<hybrid::TransitionEvent>& events);
// tsbi_candidates.csv: per event and hypothesis, every known area the arcs
// reached and what TSBI made of it (tsbi::CandidateReport): the prior of
// the robot in the area's frame (mean, standard deviations), the search
// (wide, starts), the most points a match explained, log F and the verdict
// (out_of_reach, bound, no_mode, improbable, area_check, outcome). What to
// read when a loop did not close.
void write_tsbi_candidates_csv(const std::string& path,
                               const std::vector<hybrid::TransitionEvent>& events);

// Areas with their global poses and covariances, arcs with mean, covariance
// and the number of fused measurements.
void write_topology_json(const std::string& path, const topology::HmtMap& map,
                         const global_map::GlobalPoses& poses);
void write_topology_dot(const std::string& path, const topology::HmtMap& map);

}  // namespace hmt::pipeline

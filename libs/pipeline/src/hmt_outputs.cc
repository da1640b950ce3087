#include "hmt/pipeline/hmt_outputs.h"

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

#include "hmt/common/files.h"

namespace hmt::pipeline {
namespace {

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

nlohmann::json cov_json(const Eigen::Matrix3d& c) {
  nlohmann::json j = nlohmann::json::array();
  for (int r = 0; r < 3; ++r) j.push_back({c(r, 0), c(r, 1), c(r, 2)});
  return j;
}

}  // namespace

void write_pmf_csv(const std::string& path, const std::vector<framework::StepTrace>& traces) {
  std::ostringstream o;
  o << "step,time,area,probability\n";
  for (const auto& t : traces)
    for (const auto& [area, p] : t.pmf)
      o << t.step << ',' << fmt("%.6f", t.time) << ',' << area << ',' << fmt("%.6g", p) << '\n';
  write_text_atomically(path, o.str());
}

void write_ess_csv(const std::string& path, const std::vector<framework::StepTrace>& traces) {
  std::ostringstream o;
  o << "step,time,hypothesis,probability,area,ess,particles\n";
  for (const auto& t : traces)
    for (const auto& h : t.hypotheses)
      o << t.step << ',' << fmt("%.6f", t.time) << ',' << h.id << ','
        << fmt("%.6g", h.probability) << ',' << h.area << ',' << fmt("%.4f", h.ess) << ','
        << h.particles << '\n';
  write_text_atomically(path, o.str());
}

void write_memory_csv(const std::string& path, const std::vector<framework::StepTrace>& traces) {
  constexpr double kMB = 1024.0 * 1024.0;
  std::ostringstream o;
  o << "step,time,peak_rss_mb,map_memory_mb,hypotheses,areas\n";
  for (const auto& t : traces) {
    if (t.map_memory_bytes == 0) continue;  // not sampled
    o << t.step << ',' << fmt("%.6f", t.time) << ',' << fmt("%.3f", t.peak_rss_bytes / kMB)
      << ',' << fmt("%.3f", t.map_memory_bytes / kMB) << ',' << t.hypotheses.size() << ','
      << t.areas << '\n';
  }
  write_text_atomically(path, o.str());
}

void write_process_times_csv(const std::string& path, const framework::ProcessTimes& times,
                             const std::vector<framework::StepTrace>& traces) {
  auto at = [](const std::vector<double>& v, size_t i) { return i < v.size() ? v[i] : 0.0; };
  std::ostringstream o;
  o << "step,time,metric_slam_ms,aam_ms,tsbi_ms,tlca_ms\n";
  for (size_t i = 0; i < traces.size(); ++i)
    o << traces[i].step << ',' << fmt("%.6f", traces[i].time) << ','
      << fmt("%.4f", at(times.metric_slam, traces[i].step)) << ','
      << fmt("%.4f", at(times.aam, traces[i].step)) << ','
      << fmt("%.4f", at(times.tsbi, traces[i].step)) << ','
      << fmt("%.4f", at(times.tlca, traces[i].step)) << '\n';
  write_text_atomically(path, o.str());
}

void write_tsbi_events_csv(const std::string& path,
                           const std::vector<hybrid::TransitionEvent>& events) {
  std::ostringstream o;
  o << "step,time,hypothesis,hypothesis_probability,from_area,outcome,area,"
       "log_f,probability,match_ratio,child,x,y,theta\n";
  for (const auto& ev : events)
    for (size_t i = 0; i < ev.outcomes.size(); ++i) {
      const auto& oc = ev.outcomes[i];
      o << ev.step << ',' << fmt("%.6f", ev.time) << ',' << ev.hypothesis << ','
        << fmt("%.6g", ev.parent_probability) << ',' << ev.from_area << ','
        << (oc.is_new() ? "new" : "known") << ',';
      // The area: the known one, or the id the new area got (empty when the
      // outcome was too improbable to follow).
      if (!oc.is_new()) o << oc.area;
      else if (ev.entered[i] != topology::kNoArea) o << ev.entered[i];
      o << ',' << fmt("%.4f", oc.log_f) << ',' << fmt("%.6g", oc.probability) << ','
        << fmt("%.4f", oc.match_ratio) << ',';
      if (ev.children[i] != hybrid::kNoChild) o << ev.children[i];
      // A closure's best mode: the robot in the known area's frame.
      if (!oc.is_new())
        o << ',' << fmt("%.4f", oc.robot.mean.x) << ',' << fmt("%.4f", oc.robot.mean.y) << ','
          << fmt("%.5f", oc.robot.mean.theta);
      else
        o << ",,,";
      o << '\n';
    }
  write_text_atomically(path, o.str());
}

void write_tsbi_candidates_csv(const std::string& path,
                               const std::vector<hybrid::TransitionEvent>& events) {
  std::ostringstream o;
  o << "step,time,hypothesis,from_area,area,prior_x,prior_y,prior_theta,prior_sd_x,"
       "prior_sd_y,prior_sd_theta,wide,starts,best_match_ratio,log_f,verdict\n";
  for (const auto& ev : events)
    for (const tsbi::CandidateReport& r : ev.considered) {
      o << ev.step << ',' << fmt("%.6f", ev.time) << ',' << ev.hypothesis << ','
        << ev.from_area << ',' << r.area << ',' << fmt("%.3f", r.prior_mean.x) << ','
        << fmt("%.3f", r.prior_mean.y) << ',' << fmt("%.4f", r.prior_mean.theta) << ','
        << fmt("%.3f", r.prior_sd(0)) << ',' << fmt("%.3f", r.prior_sd(1)) << ','
        << fmt("%.4f", r.prior_sd(2)) << ',' << (r.wide ? 1 : 0) << ',' << r.starts << ','
        << fmt("%.4f", r.best_ratio) << ',';
      if (r.has_log_f()) o << fmt("%.4f", r.log_f);
      o << ',' << tsbi::verdict_name(r.verdict) << '\n';
    }
  write_text_atomically(path, o.str());
}

void write_topology_json(const std::string& path, const topology::HmtMap& map,
                         const global_map::GlobalPoses& poses) {
  nlohmann::json j;
  j["root"] = poses.root;
  j["areas"] = nlohmann::json::array();
  for (topology::AreaId id : map.area_ids()) {
    const topology::Area& a = map.area(id);
    nlohmann::json ja;
    ja["id"] = id;
    ja["keyframes"] = a.keyframes.size();
    // Each keyframe's scan time and pose in the area's frame: with a
    // reference trajectory, where the area lies (scripts/closure_check.py).
    // Times to the microsecond, as the CSVs write them: a ROS bag's
    // nanosecond clock and a CARMEN log's seconds then give the same bytes.
    // Their log steps too (null where not known: a map resumed from an
    // older map file): a log whose timestamps repeat or are rounded (csail's
    // to 10 s) still says, by step, where each keyframe was taken.
    ja["keyframe_poses"] = nlohmann::json::array();
    ja["keyframe_steps"] = nlohmann::json::array();
    for (const topology::Keyframe& k : a.keyframes) {
      ja["keyframe_poses"].push_back(
          {std::round(k.scan.timestamp * 1e6) / 1e6, k.pose.x, k.pose.y, k.pose.theta});
      ja["keyframe_steps"].push_back(k.step == topology::kUnknownStep ? nlohmann::json(nullptr)
                                                                      : nlohmann::json(k.step));
    }
    ja["parent"] = a.frame.parent == topology::kNoArea ? nlohmann::json(nullptr)
                                                       : nlohmann::json(a.frame.parent);
    ja["created_step"] = a.frame.created_step;
    ja["created_time"] = a.frame.created_time;
    auto it = poses.poses.find(id);
    if (it != poses.poses.end()) {
      const auto& p = it->second;
      ja["global_pose"] = {{"x", p.mean.x}, {"y", p.mean.y}, {"theta", p.mean.theta}};
      ja["global_cov"] = cov_json(p.cov);
    }
    j["areas"].push_back(ja);
  }
  j["arcs"] = nlohmann::json::array();
  for (const auto& [key, arc] : map.arcs()) {
    j["arcs"].push_back({{"from", arc.from},
                         {"to", arc.to},
                         {"mean", {{"x", arc.pose.mean.x}, {"y", arc.pose.mean.y},
                                   {"theta", arc.pose.mean.theta}}},
                         {"cov", cov_json(arc.pose.cov)},
                         {"measurements", arc.measurements}});
  }
  write_text_atomically(path, j.dump(2) + "\n");
}

void write_topology_dot(const std::string& path, const topology::HmtMap& map) {
  std::ostringstream o;
  o << "graph hmt {\n  node [shape=circle];\n";
  for (topology::AreaId id : map.area_ids()) o << "  " << id << ";\n";
  for (const auto& [key, arc] : map.arcs())
    o << "  " << arc.from << " -- " << arc.to << " [label=\"" << arc.measurements
      << "\"];\n";
  o << "}\n";
  write_text_atomically(path, o.str());
}

}  // namespace hmt::pipeline

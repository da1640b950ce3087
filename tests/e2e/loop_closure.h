// Checks of an `hmt-slam run` output folder for a loop closed into area 1:
// TSBI weighed "a new area" against "area 1 again" at an event in an area
// numbered `from_area` or later, and area 1 won; the topology holds the
// loop's arc -- from that area into area 1, either new or, when the loop
// passed through area 2 only, the arc 1-2 fused again (Eq. 10); and the PMF
// of the topological position put area 1 above 0.9 after that event.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "run_app.h"

namespace hmt::e2e {

inline std::vector<std::vector<std::string>> read_csv(const std::string& path) {
  std::vector<std::vector<std::string>> rows;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    if (!line.empty() && line.back() == ',') cells.push_back("");
    rows.push_back(cells);
  }
  return rows;
}

inline void expect_loop_closed_into_area_1(const std::string& out, int from_area) {
  // tsbi_events.csv: step,time,hypothesis,hypothesis_probability,from_area,
  // outcome,area,log_f,probability,match_ratio,child,x,y,theta
  struct Weighed {
    double p_new = -1, p_one = -1;
    std::string from;
  };
  std::map<std::string, Weighed> events;  // by "step/hypothesis"
  for (const auto& r : read_csv(out + "/tsbi_events.csv")) {
    ASSERT_EQ(r.size(), 14u);
    // A closure's best mode (the robot in the known area's frame); none for
    // the new area.
    if (r[5] == "known")
      for (size_t c = 11; c < 14; ++c) EXPECT_TRUE(std::isfinite(std::stod(r[c]))) << r[c];
    else
      EXPECT_EQ(r[11] + r[12] + r[13], "");
    Weighed& w = events[r[0] + "/" + r[2]];
    w.from = r[4];
    if (r[5] == "new") w.p_new = std::stod(r[8]);
    if (r[5] == "known" && r[6] == "1") w.p_one = std::stod(r[8]);
  }
  long closure_step = -1;
  for (const auto& [key, w] : events)
    if (w.p_new >= 0 && w.p_one > w.p_new && std::stoi(w.from) >= from_area) {
      closure_step = std::stol(key.substr(0, key.find('/')));
      break;
    }
  ASSERT_GE(closure_step, 0) << "no event weighed a new area against area 1 with area 1 winning";

  const auto topo = nlohmann::json::parse(slurp(out + "/topology.json"));
  bool loop_arc = false;
  for (const auto& a : topo["arcs"]) {
    const int to = a["to"].get<int>();
    if (a["from"].get<int>() != 1 || to < from_area) continue;
    if (to > 2 || a["measurements"].get<int>() >= 2) loop_arc = true;
  }
  EXPECT_TRUE(loop_arc) << "the final topology has no arc from a later area into area 1";
  // Every keyframe of every area, as [time, x, y, theta] in the area's frame.
  for (const auto& a : topo["areas"]) {
    const auto& kp = a["keyframe_poses"];
    ASSERT_EQ(kp.size(), a["keyframes"].get<size_t>()) << "area " << a["id"];
    for (const auto& k : kp) {
      ASSERT_EQ(k.size(), 4u);
      for (const auto& v : k) EXPECT_TRUE(std::isfinite(v.get<double>()));
    }
    // Their log steps: known in a run from the start, ascending (an area
    // gains keyframes as the robot drives through it), none before the area
    // was first entered.
    const auto& ks = a["keyframe_steps"];
    ASSERT_EQ(ks.size(), kp.size()) << "area " << a["id"];
    uint64_t last = a["created_step"].get<uint64_t>();
    for (size_t k = 0; k < ks.size(); ++k) {
      ASSERT_TRUE(ks[k].is_number_unsigned()) << "area " << a["id"] << " keyframe " << k;
      const uint64_t step = ks[k].get<uint64_t>();
      EXPECT_TRUE(k == 0 ? step >= last : step > last) << "area " << a["id"] << " keyframe " << k;
      last = step;
    }
  }

  bool settled = false;
  for (const auto& r : read_csv(out + "/topological_pmf.csv"))
    if (std::stol(r[0]) >= closure_step && r[2] == "1" && std::stod(r[3]) > 0.9) settled = true;
  EXPECT_TRUE(settled) << "P(area 1) never exceeded 0.9 after the closure";

  const auto summary = nlohmann::json::parse(slurp(out + "/summary.json"));
  EXPECT_GE(summary["loop_closures_accepted"].get<int>(), 1);
  // The embedded logs' clocks run forward.
  EXPECT_EQ(summary["timestamps_not_increasing"].get<int>(), 0);
  // The hypothesis the outputs draw was made by some event's outcome.
  const std::string best = std::to_string(summary["best_hypothesis"].get<unsigned>());
  bool made = false;
  for (const auto& r : read_csv(out + "/tsbi_events.csv")) made |= r[10] == best;
  EXPECT_TRUE(made) << "best_hypothesis " << best << " is no event's child";
}

// tsbi_candidates.csv agrees with tsbi_events.csv: every known outcome of
// an event is a candidate reported as "outcome", with the same F, and every
// candidate reported so is one; each candidate row is well formed (a known
// verdict, finite non-negative prior deviations). Returns the rows.
inline std::vector<std::vector<std::string>> expect_candidates_agree_with_events(
    const std::string& out) {
  // tsbi_candidates.csv: step,time,hypothesis,from_area,area,prior_x,prior_y,
  // prior_theta,prior_sd_x,prior_sd_y,prior_sd_theta,wide,starts,
  // best_match_ratio,log_f,verdict
  const auto candidates = read_csv(out + "/tsbi_candidates.csv");
  std::map<std::string, std::string> reported;  // "step/hypothesis/area" -> log F
  const std::vector<std::string> verdicts = {"out_of_reach", "bound", "no_mode",
                                             "improbable", "area_check", "outcome"};
  for (const auto& r : candidates) {
    EXPECT_EQ(r.size(), 16u);
    if (r.size() != 16u) continue;
    EXPECT_NE(std::find(verdicts.begin(), verdicts.end(), r[15]), verdicts.end()) << r[15];
    for (int c : {8, 9, 10}) EXPECT_GE(std::stod(r[c]), 0.0);
    const double ratio = std::stod(r[13]);
    EXPECT_TRUE(ratio >= 0.0 && ratio <= 1.0) << ratio;
    if (r[15] == "outcome") reported[r[0] + "/" + r[2] + "/" + r[4]] = r[14];
  }
  std::map<std::string, std::string> known;
  for (const auto& r : read_csv(out + "/tsbi_events.csv"))
    if (r.size() == 14u && r[5] == "known") known[r[0] + "/" + r[2] + "/" + r[6]] = r[7];
  EXPECT_EQ(reported, known) << "the candidates reported as outcomes are not the events' known ones";
  return candidates;
}

// rtl.csv (framework.rtl_probe_hz > 0): some answer of real-time
// localization came while metric SLAM was still on a step that had been
// running for at least `long_ms` (a step with a new-area event waits for
// the area abstraction and TSBI), and it was valid.
inline void expect_rtl_answered_during_a_long_step(const std::string& csv, double long_ms) {
  std::ifstream f(csv);
  ASSERT_TRUE(f) << csv;
  std::string line;
  std::getline(f, line);
  ASSERT_EQ(line.rfind("wall_s,latency_ms,metric_busy,busy_step,busy_for_ms,answered_during_step,"
                       "step_running_ms,valid,", 0), 0u) << line;
  size_t rows = 0, during_long = 0;
  double longest = 0.0;
  while (std::getline(f, line)) {
    std::vector<std::string> c;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) c.push_back(x);
    ASSERT_GE(c.size(), 8u) << line;
    ++rows;
    const bool during = c[5] == "1", valid = c[7] == "1";
    const double running = std::stod(c[6]);
    if (during && valid && running >= long_ms) ++during_long;
    longest = std::max(longest, running);
  }
  EXPECT_GT(rows, 10u);
  EXPECT_GT(during_long, 0u) << "longest step seen running: " << longest << " ms";
}

}  // namespace hmt::e2e

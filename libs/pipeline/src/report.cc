#include "hmt/pipeline/report.h"

#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <nlohmann/json.hpp>

#include "hmt/common/error.h"
#include "hmt/common/files.h"
#include "report_assets.h"

namespace hmt::pipeline {

using nlohmann::json;

struct ReportWriter::Data {
  json root = json::object();
  // Candidate grids drawn so far, by identity: an archived area's grid is
  // shared by every event that weighed it, and is drawn once.
  std::map<const grid::OccupancyGrid*, json> drawn;
  std::map<topology::AreaId, int> versions;  // images per area so far
  std::set<std::string> images;               // closures/... written
};

namespace {

// Values rounded before they are written: the page needs millimetres and
// six decimals of probability, not seventeen digits (data.js stays small).
// Divided rather than multiplied by the unit, so the result is the double
// nearest the decimal and prints as it (0.3, not 0.30000000000000004).
double round_to(double v, double per_unit) {
  if (!std::isfinite(v)) return 0.0;
  return std::round(v * per_unit) / per_unit;
}
double metres(double v) { return round_to(v, 1e3); }
double prob(double v) { return round_to(v, 1e6); }

json pose_json(const Pose2D& p) {
  return json::array({metres(p.x), metres(p.y), round_to(p.theta, 1e4)});
}

json frame_json(const grid::MapFrame& f) {
  return {{"width", f.width},
          {"height", f.height},
          {"resolution", f.resolution},
          {"origin", json::array({f.origin_x, f.origin_y})}};
}

// The hypothesis shown at a step: the most probable, the lower id on a tie.
const framework::HypothesisTrace* most_probable(const framework::StepTrace& t) {
  const framework::HypothesisTrace* best = nullptr;
  for (const auto& h : t.hypotheses)
    if (!best || h.probability > best->probability ||
        (h.probability == best->probability && h.id < best->id))
      best = &h;
  return best;
}

}  // namespace

ReportWriter::ReportWriter(std::string out_dir)
    : dir_(std::move(out_dir) + "/report"), data_(std::make_unique<Data>()) {}

ReportWriter::~ReportWriter() = default;

void ReportWriter::add_filter(const std::vector<framework::StepTrace>& traces,
                              const std::vector<hybrid::TransitionEvent>& events,
                              const std::vector<hybrid::AcceptanceEvent>& acceptances) {
  json& root = data_->root;
  // Per step: time, P(current area) (areas below 1e-6 left out) and the
  // most probable hypothesis's ESS and particles, with the hypotheses alive.
  json steps = json::array();
  for (const framework::StepTrace& t : traces) {
    json pmf = json::array();
    for (const auto& [area, p] : t.pmf)
      if (prob(p) > 0) pmf.push_back(json::array({area, prob(p)}));
    const framework::HypothesisTrace* h = most_probable(t);
    steps.push_back({{"step", t.step},
                     {"time", round_to(t.time, 1e6)},
                     {"pmf", pmf},
                     {"hypothesis", h ? json(h->id) : json(nullptr)},
                     {"hypothesis_probability", h ? prob(h->probability) : 0.0},
                     {"ess", h ? round_to(h->ess, 1e3) : 0.0},
                     {"particles", h ? h->particles : 0},
                     {"hypotheses", t.hypotheses.size()}});
  }
  root["steps"] = steps;

  make_directories(dir_ + "/closures");
  json evs = json::array();
  for (const hybrid::TransitionEvent& ev : events) {
    json outcomes = json::array();
    for (size_t i = 0; i < ev.outcomes.size(); ++i) {
      const tsbi::Outcome& o = ev.outcomes[i];
      const topology::AreaId entered =
          i < ev.entered.size() ? ev.entered[i] : topology::kNoArea;
      const uint32_t child = i < ev.children.size() ? ev.children[i] : hybrid::kNoChild;
      json jo = {{"area", o.is_new() ? json(nullptr) : json(o.area)},
                 {"entered", entered == topology::kNoArea ? json(nullptr) : json(entered)},
                 {"child", child == hybrid::kNoChild ? json(nullptr) : json(child)},
                 {"log_f", round_to(o.log_f, 1e4)},
                 {"probability", prob(o.probability)}};
      if (!o.is_new()) {
        jo["match_ratio"] = round_to(o.match_ratio, 1e4);
        jo["prior"] = pose_json(o.prior.mean);
        jo["match"] = pose_json(o.robot.mean);
        const auto* grid = i < ev.candidate_maps.size() ? ev.candidate_maps[i].get() : nullptr;
        if (grid) {
          auto it = data_->drawn.find(grid);
          if (it == data_->drawn.end()) {
            const grid::MapImage img = grid::render(*grid);
            const std::string name = "closures/area_" + std::to_string(o.area) + "_" +
                                     std::to_string(data_->versions[o.area]++) + ".png";
            grid::write_png(img, dir_ + "/" + name);
            data_->images.insert(name);
            json view = frame_json(img.frame());
            view["image"] = name;
            it = data_->drawn.emplace(grid, view).first;
          }
          jo["grid"] = it->second;
        }
      }
      outcomes.push_back(jo);
    }
    json je = {{"step", ev.step},
               {"time", round_to(ev.time, 1e6)},
               {"hypothesis", ev.hypothesis},
               {"hypothesis_probability", prob(ev.parent_probability)},
               {"from_area", ev.from_area},
               {"outcomes", outcomes}};
    bool known = false;
    for (const tsbi::Outcome& o : ev.outcomes) known |= !o.is_new();
    // The points are what the candidates' pictures need: only then.
    if (known && ev.observed_points) {
      json pts = json::array();
      for (const Point2D& p : *ev.observed_points)
        pts.push_back(json::array({metres(p.x), metres(p.y)}));
      je["points"] = pts;
    }
    evs.push_back(je);
  }
  root["events"] = evs;

  json closures = json::array();
  for (const hybrid::AcceptanceEvent& a : acceptances)
    for (const tlca::ClosureReport& c : a.closures)
      closures.push_back({{"step", c.record.step},
                          {"accepted_step", a.step},
                          {"from", c.record.from},
                          {"to", c.record.to},
                          {"aligned", c.aligned},
                          {"consistent", c.consistent}});
  root["closures"] = closures;
}

void ReportWriter::add_map(const grid::MapFrame& frame, const std::vector<Pose2D>& trajectory,
                           uint64_t first_step,
                           const std::vector<hybrid::TrajectorySegment>& segments,
                           const topology::HmtMap& map, const global_map::GlobalPoses& poses) {
  json& root = data_->root;
  root["map"] = frame_json(frame);
  root["map"]["image"] = "../map.png";
  root["first_step"] = first_step;
  json traj = json::array();
  for (const Pose2D& p : trajectory) traj.push_back(pose_json(p));
  root["trajectory"] = traj;
  // The area of each step on the output path (a later visit wins the step
  // two visits share); 0 before the first known one.
  std::vector<topology::AreaId> area(trajectory.size(), 0);
  for (const hybrid::TrajectorySegment& s : segments)
    for (size_t k = 0; k < s.poses.size(); ++k) {
      const uint64_t step = s.first_step + k;
      if (step >= first_step && step - first_step < area.size()) area[step - first_step] = s.area;
    }
  for (size_t i = 1; i < area.size(); ++i)
    if (area[i] == 0) area[i] = area[i - 1];
  root["step_area"] = area;
  json areas = json::array();
  for (topology::AreaId id : map.area_ids()) {
    const topology::Area& a = map.area(id);
    json ja = {{"id", id},
               {"created_step", a.frame.created_step},
               {"keyframes", a.keyframes.size()}};
    auto it = poses.poses.find(id);
    ja["pose"] = it == poses.poses.end() ? json(nullptr) : pose_json(it->second.mean);
    areas.push_back(ja);
  }
  root["areas"] = areas;
  json arcs = json::array();
  for (const auto& [key, arc] : map.arcs())
    arcs.push_back({{"from", arc.from}, {"to", arc.to}, {"measurements", arc.measurements}});
  root["arcs"] = arcs;
}

std::string ReportWriter::write(const std::string& summary_json) {
  json& root = data_->root;
  json summary;
  try {
    summary = json::parse(summary_json);
  } catch (const json::exception& e) {
    throw Error(ExitCode::kInternal, std::string("report: summary.json: ") + e.what());
  }
  // The run's totals, but none that measure the machine (times, memory):
  // the same run gives the same report.
  root["summary"] = json::object();
  for (const char* key : {"input", "scans", "particles", "areas", "arcs", "keyframes",
                          "new_area_events", "transitions_evaluated", "loop_closures_accepted",
                          "loop_closures_inconsistent", "max_hypotheses_alive",
                          "hypotheses_at_end", "final_pose", "framework_mode"})
    if (summary.contains(key)) root["summary"][key] = summary[key];
  root["format"] = 1;
  make_directories(dir_);
  // Images an earlier run into this folder drew and this one did not: gone,
  // so the folder holds this run's report only.
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir_ + "/closures", ec)) {
    const std::string name = "closures/" + e.path().filename().string();
    if (e.path().extension() == ".png" && !data_->images.count(name))
      std::filesystem::remove(e.path(), ec);
  }
  // A script that sets a global: a page opened from file:// may run a
  // script beside it but not fetch a JSON file.
  write_text_atomically(dir_ + "/data.js", "window.HMT_REPORT = " + root.dump() + ";\n");
  write_text_atomically(dir_ + "/report.js", report_assets::kReportJs);
  write_text_atomically(dir_ + "/report.css", report_assets::kReportCss);
  write_text_atomically(dir_ + "/index.html", report_assets::kIndexHtml);
  return dir_ + "/index.html";
}

}  // namespace hmt::pipeline

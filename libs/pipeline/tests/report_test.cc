// The report writer on a small hand-made run: what data.js holds, the
// candidate grids drawn once each, the page's files, the same bytes twice.
#include "hmt/pipeline/report.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "hmt_test/scratch.h"

namespace hmt::pipeline {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// A fresh folder, removed if the test passes.
fs::path fresh_dir(const std::string& name) {
  return scratch::folder("report_" + name);
}

framework::StepTrace trace(uint64_t step, std::map<topology::AreaId, double> pmf,
                           std::vector<framework::HypothesisTrace> hyps) {
  framework::StepTrace t;
  t.step = step;
  t.time = 100.0 + step;
  t.pmf = std::move(pmf);
  t.hypotheses = std::move(hyps);
  return t;
}

tsbi::Outcome known(topology::AreaId area, double p, Pose2D prior, Pose2D match) {
  tsbi::Outcome o;
  o.area = area;
  o.probability = p;
  o.log_f = 3.0;
  o.match_ratio = 0.75;
  o.prior.mean = prior;
  o.robot.mean = match;
  return o;
}

tsbi::Outcome new_area(double p) {
  tsbi::Outcome o;
  o.probability = p;
  o.log_f = 1.0;
  return o;
}

// Writes the report of a four-step run with two areas into `out`; returns data.js's JSON.
json write_run(const fs::path& out) {
  std::vector<framework::StepTrace> traces = {
      trace(0, {{1, 1.0}}, {{1, 1.0, 1, 28.0, 30}}),
      trace(1, {{1, 1.0}}, {{1, 1.0, 1, 27.5, 30}}),
      trace(2, {{1, 0.3}, {2, 0.7}}, {{2, 0.4, 2, 10.0, 30}, {1, 0.6, 1, 20.0, 30}}),
      trace(3, {{1, 0.3}, {2, 0.7}}, {{2, 0.4, 2, 11.0, 30}, {1, 0.6, 1, 21.0, 30}})};

  auto grid = std::make_shared<const grid::OccupancyGrid>(0.1);
  auto points = std::make_shared<const std::vector<Point2D>>(
      std::vector<Point2D>{{1.0, 2.0}, {3.0004, -1.0}});
  std::vector<hybrid::TransitionEvent> events(3);
  // Two events weigh area 1's same grid: it is drawn once.
  for (int k = 0; k < 2; ++k) {
    hybrid::TransitionEvent& ev = events[k];
    ev.step = 2;
    ev.hypothesis = 1 + k;
    ev.parent_probability = 0.5;
    ev.from_area = 2;
    ev.outcomes = {new_area(0.2), known(1, 0.8, {1, 0, 0}, {0.5, 0, 0.1})};
    ev.children = {3, hybrid::kNoChild};
    ev.entered = {2, topology::kNoArea};
    ev.observed_points = points;
    ev.candidate_maps = {nullptr, grid};
  }
  // A new area only: listed, no points.
  events[2].step = 3;
  events[2].outcomes = {new_area(1.0)};
  events[2].children = {4};
  events[2].entered = {3};
  events[2].observed_points = points;
  events[2].candidate_maps = {nullptr};

  ReportWriter w(out.string());
  w.add_filter(traces, events, {});

  topology::HmtMap map;
  map.add_area(1);
  topology::ReferenceFrame f2;
  f2.parent = 1;
  f2.created_step = 3;
  map.add_area(2, f2);
  map.add_arc_measurement(1, 2, PoseGaussian(Pose2D(2, 0, 0), Eigen::Matrix3d::Identity()));
  global_map::GlobalPoses poses;
  poses.root = 1;
  poses.poses[1] = PoseGaussian();
  poses.poses[2] = PoseGaussian(Pose2D(2, 0, 0));
  // Step 2 is in no segment: it keeps the area of step 1.
  std::vector<hybrid::TrajectorySegment> segs(2);
  segs[0].area = 1;
  segs[0].first_step = 0;
  segs[0].poses = {Pose2D(), Pose2D(0.5, 0, 0)};
  segs[1].area = 2;
  segs[1].first_step = 3;
  segs[1].poses = {Pose2D()};
  const std::vector<Pose2D> traj = {Pose2D(), Pose2D(0.5, 0, 0), Pose2D(1, 0, 0),
                                    Pose2D(2.123456, 0, 0)};
  grid::MapFrame frame{100, 80, 0.05, -1.0, -2.0};
  w.add_map(frame, traj, 0, segs, map, poses);
  const std::string index =
      w.write(R"({"input": "log.rawlog", "scans": 4, "wall_time_s": 1.25, "peak_rss_mb": 30})");
  EXPECT_EQ(index, out.string() + "/report/index.html");

  const std::string text = slurp(out / "report" / "data.js");
  const std::string prefix = "window.HMT_REPORT = ";
  EXPECT_EQ(text.rfind(prefix, 0), 0u);
  EXPECT_EQ(text.substr(text.size() - 2), ";\n");
  return json::parse(text.substr(prefix.size(), text.size() - prefix.size() - 2));
}

TEST(Report, DataHoldsTheRunStepByStep) {
  const fs::path out = fresh_dir("data");
  const json d = write_run(out);
  EXPECT_EQ(d["format"], 1);
  ASSERT_EQ(d["steps"].size(), 4u);
  // The most probable hypothesis's ESS, and how many are alive.
  EXPECT_EQ(d["steps"][2]["hypothesis"], 1);
  EXPECT_DOUBLE_EQ(d["steps"][2]["ess"].get<double>(), 20.0);
  EXPECT_EQ(d["steps"][2]["hypotheses"], 2);
  EXPECT_EQ(d["steps"][2]["pmf"], json::parse("[[1, 0.3], [2, 0.7]]"));
  EXPECT_EQ(d["step_area"], json::parse("[1, 1, 1, 2]"));
  EXPECT_DOUBLE_EQ(d["trajectory"][3][0].get<double>(), 2.123);  // millimetres
  EXPECT_EQ(d["map"]["image"], "../map.png");
  EXPECT_EQ(d["map"]["width"], 100);
  EXPECT_EQ(d["map"]["origin"], json::parse("[-1.0, -2.0]"));
  ASSERT_EQ(d["areas"].size(), 2u);
  EXPECT_EQ(d["areas"][1]["created_step"], 3);
  EXPECT_EQ(d["areas"][1]["pose"], json::parse("[2.0, 0.0, 0.0]"));
  EXPECT_EQ(d["arcs"].size(), 1u);
  // The summary without what measures the machine.
  EXPECT_EQ(d["summary"]["scans"], 4);
  EXPECT_FALSE(d["summary"].contains("wall_time_s"));
  EXPECT_FALSE(d["summary"].contains("peak_rss_mb"));
}

TEST(Report, CandidatesCarryBothPosesTheirPointsAndOneImagePerGrid) {
  const fs::path out = fresh_dir("events");
  // An earlier run's image, which this run does not draw, goes.
  fs::create_directories(out / "report" / "closures");
  std::ofstream(out / "report" / "closures" / "area_9_0.png") << "an earlier run's";
  const json d = write_run(out);
  ASSERT_EQ(d["events"].size(), 3u);
  const json& o = d["events"][0]["outcomes"][1];
  EXPECT_EQ(o["area"], 1);
  EXPECT_EQ(o["prior"], json::parse("[1.0, 0.0, 0.0]"));
  EXPECT_EQ(o["match"], json::parse("[0.5, 0.0, 0.1]"));
  EXPECT_EQ(o["child"], nullptr);
  EXPECT_EQ(d["events"][0]["outcomes"][0]["area"], nullptr);
  EXPECT_EQ(d["events"][0]["outcomes"][0]["entered"], 2);
  EXPECT_EQ(d["events"][0]["points"], json::parse("[[1.0, 2.0], [3.0, -1.0]]"));
  EXPECT_EQ(o["grid"]["image"], "closures/area_1_0.png");
  EXPECT_EQ(d["events"][1]["outcomes"][1]["grid"], o["grid"]);
  EXPECT_FALSE(d["events"][2].contains("points"));  // no known area weighed
  size_t images = 0;
  for (const auto& e : fs::directory_iterator(out / "report" / "closures")) {
    ++images;
    EXPECT_EQ(e.path().filename(), "area_1_0.png");
  }
  EXPECT_EQ(images, 1u);
  for (const char* name : {"index.html", "report.js", "report.css"})
    EXPECT_GT(fs::file_size(out / "report" / name), 100u) << name;
  const std::string page = slurp(out / "report" / "index.html");
  EXPECT_NE(page.find("<script src=\"data.js\"></script>"), std::string::npos);
  EXPECT_NE(page.find("<script src=\"report.js\"></script>"), std::string::npos);
}

TEST(Report, TheSameRunGivesTheSameBytes) {
  const fs::path a = fresh_dir("same_a"), b = fresh_dir("same_b");
  write_run(a);
  write_run(b);
  for (const char* name : {"data.js", "index.html", "report.js", "closures/area_1_0.png"})
    EXPECT_EQ(slurp(a / "report" / name), slurp(b / "report" / name)) << name;
}

}  // namespace
}  // namespace hmt::pipeline

// hmt-slam run on the embedded logs: scan counts, outputs, the final pose
// against an independent reference, and determinism.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "hmt/common/pose2d.h"
#include "hmt/grouping/scan_poses.h"
#include "hmt/io/tum.h"
#include "loop_closure.h"
#include "run_app.h"

namespace hmt::e2e {
namespace {
namespace fs = std::filesystem;

Pose2D reference_final_pose() {
  std::ifstream f(std::string(HMT_SOURCE_DIR) + "/tests/reference/malaga_final_pose.txt");
  std::string line;
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream is(line);
    Pose2D p;
    is >> p.x >> p.y >> p.theta;
    return p;
  }
  ADD_FAILURE() << "no reference pose";
  return {};
}

TEST(AppRun, MalagaOneLoopMatchesIndependentReference) {
  const std::string dir = temp_dir("malaga");
  // The default: the five concurrent processes, deterministic mode; RTL
  // probed 200 times a second.
  const AppResult r = run_app("run --config config/default.ini --quiet --set framework.rtl_probe_hz=200 --out '" + dir + "/out'", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("map image: "), std::string::npos) << r.out;

  const auto summary = nlohmann::json::parse(slurp(dir + "/out/summary.json"));
  // 225 sensory frames, each with one scan (the first has no action before it).
  EXPECT_EQ(summary["scans"].get<int>(), 225);
  const auto traj = io::read_tum(dir + "/out/trajectory.tum");
  ASSERT_EQ(traj.size(), 225u);
  for (const char* f : {"map.png", "map.pgm", "map.yaml", "config_effective.ini"})
    EXPECT_TRUE(fs::exists(dir + "/out/" + f)) << f;

  const Pose2D ref = reference_final_pose();
  const Pose2D got = traj.back().pose;
  EXPECT_LT(std::hypot(got.x - ref.x, got.y - ref.y), 0.3)
      << "final pose " << got.x << " " << got.y << " " << got.theta;
  EXPECT_LT(std::fabs(wrap_angle(got.theta - ref.theta)), 0.03);
  EXPECT_NEAR(summary["final_pose"]["x"].get<double>(), got.x, 1e-5);
  // The metric filter's scans matched their maps: hardly a particle-step
  // fell back to the odometry, and the run gave no warning about it. The
  // log's scans lie 0.33 m apart (median): at the 0.5 m spacing the filter
  // skips some on the straights (165 of the 225 are filtered), never more
  // than every other one.
  const auto& m = summary["metric_slam"];
  EXPECT_GT(m["scans_filtered"].get<int>(), 225 / 2);
  EXPECT_LE(m["scans_filtered"].get<int>(), 225);
  EXPECT_GE(m["particle_moves"].get<int>(), (m["scans_filtered"].get<int>() - 1) * 10);
  EXPECT_LT(m["odometry_fallback_fraction"].get<double>(), 0.01);
  EXPECT_EQ(r.err.find("odometry alone"), std::string::npos) << r.err;

  // The HMT outputs, and the loop closed by inference when the robot comes
  // back to its start.
  for (const char* f : {"map_topology.png", "hmt_map.bin", "topology.json", "topology.dot",
                        "topological_pmf.csv", "tsbi_events.csv", "tsbi_candidates.csv",
                        "memory.csv", "ess.csv", "process_times.csv", "rtl.csv",
                        "areas/area_1.png"})
    EXPECT_TRUE(fs::exists(dir + "/out/" + f)) << f;
  expect_loop_closed_into_area_1(dir + "/out", 3);
  // The closure's event also reported area 1 among its candidates, and some
  // event reported an area it did not take and why.
  const auto candidates = expect_candidates_agree_with_events(dir + "/out");
  EXPECT_TRUE(std::any_of(candidates.begin(), candidates.end(), [](const auto& r) {
    return r.size() == 16u && r[15] != "outcome";
  }));
  expect_rtl_answered_during_a_long_step(dir + "/out/rtl.csv", 20.0);
}

TEST(AppRun, ResumeContinuesASavedRunAndClosesTheLoop) {
  const std::string dir = temp_dir("resume");
  // The first 120 scans, saved; then the rest of the log from hmt_map.bin.
  const AppResult a = run_app("run --config config/default.ini --quiet --set input.max_steps=120 --out '" + dir + "/first'", dir);
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const AppResult b = run_app("resume --config config/default.ini --quiet --map '" + dir +
                                  "/first/hmt_map.bin' --set input.first_step=120 --out '" + dir + "/rest'",
                              dir);
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const auto traj = io::read_tum(dir + "/rest/trajectory.tum");
  ASSERT_EQ(traj.size(), 105u);
  // It continues where the saved run stopped and ends where the whole run
  // does (the independent reference), the loop closed after the resume.
  const auto first = io::read_tum(dir + "/first/trajectory.tum");
  const Pose2D d = traj.front().pose - first.back().pose;
  EXPECT_LT(d.norm(), 1.0);  // one step of motion apart
  const Pose2D ref = reference_final_pose(), got = traj.back().pose;
  EXPECT_LT(std::hypot(got.x - ref.x, got.y - ref.y), 0.3)
      << "final pose " << got.x << " " << got.y << " " << got.theta;
  expect_loop_closed_into_area_1(dir + "/rest", 3);

  // A damaged map file: a clear error, and the earlier outputs untouched.
  const std::string bad = dir + "/bad.bin";
  {
    const std::string bytes = slurp(dir + "/first/hmt_map.bin");
    std::ofstream(bad, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  const std::string before = slurp(dir + "/rest/trajectory.tum");
  const AppResult c = run_app("resume --config config/default.ini --quiet --map '" + bad +
                                  "' --set input.first_step=120 --out '" + dir + "/rest'",
                              dir);
  EXPECT_EQ(c.exit_code, 4) << c.err;
  EXPECT_NE(c.err.find("bad.bin"), std::string::npos) << c.err;
  EXPECT_NE(c.err.find("truncated"), std::string::npos) << c.err;
  EXPECT_EQ(slurp(dir + "/rest/trajectory.tum"), before);
  const AppResult m = run_app("resume --config config/default.ini --quiet --map '" + dir +
                                  "/missing.bin' --out '" + dir + "/rest'", dir);
  EXPECT_EQ(m.exit_code, 4) << m.err;
}

// Position RMSE of `est` against `ref` (matched by index) after the best
// rigid 2D alignment (the closed-form 2D Procrustes solution).
double aligned_rmse(const std::vector<io::StampedPose>& est,
                    const std::vector<io::StampedPose>& ref) {
  const size_t n = std::min(est.size(), ref.size());
  double ex = 0, ey = 0, rx = 0, ry = 0;
  for (size_t i = 0; i < n; ++i) {
    ex += est[i].pose.x, ey += est[i].pose.y, rx += ref[i].pose.x, ry += ref[i].pose.y;
  }
  ex /= n, ey /= n, rx /= n, ry /= n;
  double sc = 0, ss = 0;
  for (size_t i = 0; i < n; ++i) {
    const double ax = est[i].pose.x - ex, ay = est[i].pose.y - ey;
    const double bx = ref[i].pose.x - rx, by = ref[i].pose.y - ry;
    sc += ax * bx + ay * by;
    ss += ax * by - ay * bx;
  }
  const double t = std::atan2(ss, sc), c = std::cos(t), s = std::sin(t);
  double sum = 0;
  for (size_t i = 0; i < n; ++i) {
    const double ax = est[i].pose.x - ex, ay = est[i].pose.y - ey;
    const double dx = c * ax - s * ay + rx - ref[i].pose.x;
    const double dy = s * ax + c * ay + ry - ref[i].pose.y;
    sum += dx * dx + dy * dy;
  }
  return std::sqrt(sum / n);
}

TEST(AppRun, EdmontonClosesItsLoopAndFollowsTheReference) {
  const std::string dir = temp_dir("edmonton_loop");
  const AppResult r = run_app("run --config config/edmonton.ini --quiet --out '" + dir + "/out'", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Some new-area event was won by a known area, and the closure accepted.
  bool known_won = false;
  std::map<std::string, std::pair<double, double>> best;  // event -> (new, best known)
  for (const auto& row : read_csv(dir + "/out/tsbi_events.csv")) {
    auto& b = best[row[0] + "/" + row[2]];
    if (row[5] == "new") b.first = std::stod(row[8]);
    if (row[5] == "known") b.second = std::max(b.second, std::stod(row[8]));
  }
  for (const auto& [event, p] : best) known_won |= p.second > p.first;
  EXPECT_TRUE(known_won) << "no new-area event was won by a known area";
  const auto summary = nlohmann::json::parse(slurp(dir + "/out/summary.json"));
  EXPECT_GE(summary["loop_closures_accepted"].get<int>(), 1);
  // The global trajectory against the log's reference (GMapping's, good to a
  // few cm): the area-grain map scored 0.35 m, the keyframe map 0.17-0.27 m.
  const auto est = io::read_tum(dir + "/out/trajectory.tum");
  const auto ref = grouping::read_pose_file(std::string(HMT_SOURCE_DIR) + "/datasets/edmonton.reference.txt.gz");
  ASSERT_EQ(est.size(), ref.size());
  EXPECT_LT(aligned_rmse(est, ref), 0.3);
}

TEST(AppRun, MetricBaselineMatchesIndependentReference) {
  const std::string dir = temp_dir("malaga_metric");
  const AppResult r =
      run_app("metric --config config/default.ini --quiet --out '" + dir + "/out'", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto traj = io::read_tum(dir + "/out/trajectory.tum");
  ASSERT_EQ(traj.size(), 225u);
  const Pose2D ref = reference_final_pose(), got = traj.back().pose;
  EXPECT_LT(std::hypot(got.x - ref.x, got.y - ref.y), 0.3);
  // Its scans matched: no warning, hardly a fallback.
  const auto s = nlohmann::json::parse(slurp(dir + "/out/summary.json"));
  EXPECT_LT(s["odometry_fallback_fraction"].get<double>(), 0.01);
  EXPECT_GT(s["particle_moves"].get<double>(), 0);
  EXPECT_EQ(r.err.find("odometry alone"), std::string::npos) << r.err;
}

TEST(AppRun, SameSeedSameBytesWhateverTheThreads) {
  const std::string dir = temp_dir("determinism");
  const std::string base = "run --config config/default.ini --quiet --set input.max_steps=80 ";
  // Both pools: the particles' and the partitioner's SSO pairs.
  const AppResult a = run_app(
      base + "--set metric_slam.threads=1 --set area.threads=1 --out '" + dir + "/a'", dir);
  const AppResult b = run_app(
      base + "--set metric_slam.threads=2 --set area.threads=3 --out '" + dir + "/b'", dir);
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  // The same run again: the concurrent pipeline's thread timing differs,
  // the outputs do not.
  const AppResult a2 = run_app(
      base + "--set metric_slam.threads=1 --set area.threads=1 --out '" + dir + "/a2'", dir);
  ASSERT_EQ(a2.exit_code, 0) << a2.err;
  for (const char* f : {"trajectory.tum", "map.png", "map.pgm", "map.yaml", "hmt_map.bin",
                        "topology.json", "tsbi_events.csv", "tsbi_candidates.csv",
                        "topological_pmf.csv", "ess.csv"}) {
    EXPECT_EQ(slurp(dir + "/a/" + f), slurp(dir + "/b/" + f)) << f;
    EXPECT_EQ(slurp(dir + "/a/" + f), slurp(dir + "/a2/" + f)) << f;
  }
  EXPECT_NE(slurp(dir + "/a/tsbi_events.csv").find("\n"), std::string::npos);
  // A different seed gives a different run (the check above is not vacuous).
  const AppResult c = run_app(base + "--set metric_slam.seed=9 --out '" + dir + "/c'", dir);
  ASSERT_EQ(c.exit_code, 0) << c.err;
  EXPECT_NE(slurp(dir + "/a/trajectory.tum"), slurp(dir + "/c/trajectory.tum"));
}

TEST(AppRun, CarmenLogAndItsRawlogConversion) {
  const std::string dir = temp_dir("carmen");
  const AppResult r = run_app("run --config config/edmonton.ini --quiet --set input.max_steps=60 --out '" +
                                  dir + "/carmen'", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto traj = io::read_tum(dir + "/carmen/trajectory.tum");
  ASSERT_EQ(traj.size(), 60u);

  for (const char* format : {"sf", "obs"}) {
    SCOPED_TRACE(format);
    const std::string raw = dir + "/edmonton_" + format + ".rawlog";
    const AppResult c = run_app("convert --input datasets/edmonton.log.gz --output '" + raw +
                                    "' --format " + format, dir);
    ASSERT_EQ(c.exit_code, 0) << c.err;
    EXPECT_NE(c.out.find("340 scans"), std::string::npos) << c.out;
    const std::string out = dir + "/raw_" + format;
    const AppResult s = run_app("run --config config/default.ini --quiet --input '" + raw +
                                    "' --set input.max_steps=60 --out '" + out + "'", dir);
    ASSERT_EQ(s.exit_code, 0) << s.err;
    const auto t2 = io::read_tum(out + "/trajectory.tum");
    ASSERT_EQ(t2.size(), 60u);
    // Timestamps survive the conversion.
    for (size_t i = 0; i < t2.size(); ++i) EXPECT_NEAR(t2[i].timestamp, traj[i].timestamp, 1e-5);
  }
}

TEST(AppRun, EffectiveConfigRecordsOverrides) {
  const std::string dir = temp_dir("effective");
  const AppResult r = run_app("run --config config/default.ini --quiet --set input.max_steps=5 "
                              "--set metric_slam.particles=7 --out '" + dir + "/o'", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string eff = slurp(dir + "/o/config_effective.ini");
  EXPECT_NE(eff.find("particles = 7"), std::string::npos) << eff;
  EXPECT_NE(eff.find("[scan_matcher]"), std::string::npos);
}

TEST(AppRun, ScansThatMatchNoMapAreReported) {
  // Matched within 1 m, Malaga's outdoor scans keep almost no returns: the
  // particles move by the odometry. The summary counts it and the run says
  // so, naming what to check; the outputs are still written.
  const std::string dir = temp_dir("fallbacks");
  const AppResult r = run_app("run --config config/default.ini --quiet --set input.max_steps=60 "
                              "--set scan_matcher.max_range=1 --out '" + dir + "/o'", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto m = nlohmann::json::parse(slurp(dir + "/o/summary.json"))["metric_slam"];
  const double moves = m["particle_moves"].get<double>();
  ASSERT_GT(moves, 0);
  EXPECT_DOUBLE_EQ(m["odometry_fallback_fraction"].get<double>(),
                   m["odometry_fallbacks"].get<double>() / moves);
  EXPECT_GT(m["odometry_fallback_fraction"].get<double>(), 0.5);
  EXPECT_NE(r.err.find("the odometry alone moved them"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("max_range"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(dir + "/o/map.png"));

  // The metric-only tool fails the same way and says the same, with the
  // counts at its summary's top level.
  const AppResult mr = run_app("metric --config config/default.ini --quiet --set input.max_steps=60 "
                               "--set scan_matcher.max_range=1 --out '" + dir + "/m'", dir);
  ASSERT_EQ(mr.exit_code, 0) << mr.err;
  const auto ms = nlohmann::json::parse(slurp(dir + "/m/summary.json"));
  EXPECT_GT(ms["odometry_fallback_fraction"].get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(ms["odometry_fallback_fraction"].get<double>(),
                   ms["odometry_fallbacks"].get<double>() / ms["particle_moves"].get<double>());
  EXPECT_NE(mr.err.find("the odometry alone moved them"), std::string::npos) << mr.err;
  EXPECT_TRUE(fs::exists(dir + "/m/map.png"));
}

TEST(AppRun, ProgressEndsWithEveryScanCounted) {
  // Metric SLAM runs behind the feeding of the log, so the last progress
  // line before the end may lag; the closing line counts every scan.
  const std::string dir = temp_dir("progress");
  const AppResult r =
      run_app("run --config config/default.ini --set input.max_steps=60 --out '" + dir + "/o'", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE((r.out + r.err).find("done: 60 scans"), std::string::npos) << r.out << r.err;
}

}  // namespace
}  // namespace hmt::e2e

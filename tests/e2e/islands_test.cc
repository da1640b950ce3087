// `hmt-slam islands` as a user runs it: on a map_server map, on a run's
// hmt_map.bin, and on bad input (one clear error line, its exit code).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "hmt/common/error.h"
#include "run_app.h"

namespace hmt::e2e {
namespace {
namespace fs = std::filesystem;

std::string last_line(std::string s) {
  while (!s.empty() && s.back() == '\n') s.pop_back();
  const auto p = s.rfind('\n');
  return p == std::string::npos ? s : s.substr(p + 1);
}

// A 12 x 8 m building at 0.1 m: a room with a corridor leaving it, unknown
// space around. Written as map.pgm + map.yaml.
void write_building(const std::string& dir) {
  const int w = 120, h = 80;
  std::string px(static_cast<size_t>(w * h), static_cast<char>(205));
  const auto set = [&](int x, int y, uint8_t v) { px[static_cast<size_t>(y) * w + x] = static_cast<char>(v); };
  // Room (10..50) x (10..70) in image pixels, corridor (50..110) x (35..45).
  for (int y = 10; y <= 70; ++y)
    for (int x = 10; x <= 50; ++x) set(x, y, (x == 10 || x == 50 || y == 10 || y == 70) ? 0 : 254);
  for (int y = 35; y <= 45; ++y)
    for (int x = 50; x <= 110; ++x) set(x, y, (y == 35 || y == 45 || x == 110) ? 0 : 254);
  std::ofstream(dir + "/map.pgm", std::ios::binary) << "P5\n" << w << " " << h << "\n255\n" << px;
  std::ofstream(dir + "/map.yaml") << "image: map.pgm\nresolution: 0.1\norigin: [-2.0, -1.0, 0.0]\n"
                                      "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
}

void expect_outputs(const std::string& out) {
  for (const char* f : {"distinctiveness.png", "islands.png", "distinctiveness.pgm",
                        "distinctiveness.yaml", "distinctiveness.csv", "islands.csv",
                        "islands.json", "config_effective.ini"})
    EXPECT_TRUE(fs::exists(out + "/" + f)) << f;
  EXPECT_EQ(slurp(out + "/distinctiveness.png").substr(1, 3), "PNG");
}

TEST(Islands, OnAMapServerMap) {
  const std::string dir = temp_dir("islands_pgm");
  write_building(dir);
  const AppResult r = run_app("islands --map '" + dir + "/map.yaml' --out '" + dir + "/o'", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_outputs(dir + "/o");
  EXPECT_NE(r.out.find("heat map: "), std::string::npos) << r.out;
  const nlohmann::json j = nlohmann::json::parse(slurp(dir + "/o/islands.json"));
  EXPECT_EQ(j["width"], 120);
  EXPECT_EQ(j["height"], 80);
  ASSERT_GE(j["islands"].size(), 1u);
  // The best island is in the room or at the corridor's dead end, not in
  // the corridor's middle (x from 3 to 8 m, y 3 m in the map frame).
  const double x = j["islands"][0]["x"], y = j["islands"][0]["y"];
  EXPECT_FALSE(x > 4.0 && x < 7.0 && y > 2.5 && y < 3.5) << x << ", " << y;
  // The PGM of R lines up with the map: same size, placed by its .yaml.
  EXPECT_EQ(slurp(dir + "/o/distinctiveness.pgm").substr(0, 2), "P5");
  EXPECT_NE(slurp(dir + "/o/distinctiveness.yaml").find("origin: [-2.000000, -1.000000"),
            std::string::npos);
  // Deterministic: a second run writes the same values.
  const AppResult again =
      run_app("islands --map '" + dir + "/map.pgm' --out '" + dir + "/o2'", dir);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(slurp(dir + "/o/distinctiveness.csv"), slurp(dir + "/o2/distinctiveness.csv"));
  EXPECT_EQ(slurp(dir + "/o/islands.csv"), slurp(dir + "/o2/islands.csv"));
  // The localization check: one line per sample, and its correlation.
  const AppResult check = run_app("islands --check --set islands_check.samples=40 --map '" + dir +
                                      "/map.yaml' --out '" + dir + "/o3'", dir);
  ASSERT_EQ(check.exit_code, 0) << check.err;
  EXPECT_NE(check.out.find("Spearman"), std::string::npos) << check.out;
  const std::string csv = slurp(dir + "/o3/localization_check.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 41);
  EXPECT_EQ(nlohmann::json::parse(slurp(dir + "/o3/islands.json"))["check"]["samples"], 40);
}

TEST(Islands, OnARunsHmtMap) {
  const std::string dir = temp_dir("islands_run");
  const AppResult run = run_app("run --config config/default.ini --quiet --set input.max_steps=150 --out '" +
                                    dir + "/run'", dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const AppResult r = run_app("islands --config config/default.ini --set islands.stride=2 --map '" +
                                  dir + "/run/hmt_map.bin'", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expect_outputs(dir + "/run/islands");  // the default: beside the map
  EXPECT_NE(r.out.find("HMT map"), std::string::npos) << r.out;
  EXPECT_NE(slurp(dir + "/run/islands/config_effective.ini").find("stride = 2"), std::string::npos);
}

TEST(Islands, BadInputIsAClearError) {
  const std::string dir = temp_dir("islands_bad");
  const auto expect_error = [&](const std::string& args, ExitCode code, const std::string& mention) {
    SCOPED_TRACE(args);
    const AppResult r = run_app("islands " + args + " --out '" + dir + "/o'", dir);
    EXPECT_EQ(r.exit_code, static_cast<int>(code)) << r.err;
    const std::string line = last_line(r.err);
    EXPECT_EQ(line.rfind("hmt-slam: error: ", 0), 0u) << r.err;
    EXPECT_NE(line.find(mention), std::string::npos) << line;
  };
  expect_error("--map '" + dir + "/missing.yaml'", ExitCode::kInput, "missing.yaml");
  std::ofstream(dir + "/bad.yaml") << "image: map.pgm\nresolution: fine\norigin: [0, 0, 0]\n";
  expect_error("--map '" + dir + "/bad.yaml'", ExitCode::kInput, "resolution");
  std::ofstream(dir + "/junk.bin") << "HMTSESS\x1a and then nothing sensible";
  expect_error("--map '" + dir + "/junk.bin'", ExitCode::kInput, "junk.bin");
  write_building(dir);
  expect_error("--map '" + dir + "/map.yaml' --set islands.raise=2", ExitCode::kConfig, "raise");
  expect_error("--map '" + dir + "/map.yaml' --set islands.cutoff=0", ExitCode::kConfig, "cutoff");
  EXPECT_FALSE(fs::exists(dir + "/o/distinctiveness.png"));
  const AppResult none = run_app("islands", dir);
  EXPECT_EQ(none.exit_code, static_cast<int>(ExitCode::kUsage));
}

}  // namespace
}  // namespace hmt::e2e

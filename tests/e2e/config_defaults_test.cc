// hmt-slam without a configuration file: its built-in defaults are
// config/default.ini, `config --dump` prints them, --config and --set layer
// on them, and `--version` says which program this is.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "hmt/common/error.h"
#include "run_app.h"

namespace hmt::e2e {
namespace {
namespace fs = std::filesystem;

class ConfigDefaults : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = temp_dir(::testing::UnitTest::GetInstance()->current_test_info()->name());
  }
  std::string dir_;
};

TEST_F(ConfigDefaults, DumpPrintsConfigDefaultIni) {
  const AppResult r = run_app("config --dump", dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, slurp(std::string(HMT_SOURCE_DIR) + "/config/default.ini"));
}

// A run with no --config is the run with --config config/default.ini: the
// same effective configuration and, byte for byte, the same outputs.
TEST_F(ConfigDefaults, RunWithoutConfigIsTheDefaultIniRun) {
  const std::string args =
      "--quiet --input datasets/edmonton.log.gz --set input.max_steps=60 --set output.png=false";
  const AppResult bare = run_app("run " + args + " --out '" + dir_ + "/bare'", dir_);
  ASSERT_EQ(bare.exit_code, 0) << bare.err;
  const AppResult file =
      run_app("run --config config/default.ini " + args + " --out '" + dir_ + "/file'", dir_);
  ASSERT_EQ(file.exit_code, 0) << file.err;
  for (const char* name : {"config_effective.ini", "trajectory.tum", "topology.json", "map.pgm"}) {
    SCOPED_TRACE(name);
    const std::string a = slurp(dir_ + "/bare/" + name);
    EXPECT_FALSE(a.empty());
    EXPECT_EQ(a, slurp(dir_ + "/file/" + name));
  }
  // The effective configuration names the log given and the values set.
  const std::string eff = slurp(dir_ + "/bare/config_effective.ini");
  EXPECT_NE(eff.find("max_steps = 60"), std::string::npos) << eff;
  EXPECT_NE(eff.find("particles = 30"), std::string::npos) << eff;
  // MRPT maps only when asked for.
  EXPECT_FALSE(fs::exists(dir_ + "/bare/map.gridmap.gz"));
  EXPECT_FALSE(fs::exists(dir_ + "/bare/keyframes.simplemap"));
}

// hmt-partition starts from the same built-in defaults.
TEST_F(ConfigDefaults, PartitionWithoutConfigIsTheDefaultIniRun) {
  const std::string args = "--quiet --set input.max_steps=60 --set output.pgm=false ";
  const AppResult bare = run_binary(HMT_PARTITION_BIN, args + "--out '" + dir_ + "/bare'", dir_);
  ASSERT_EQ(bare.exit_code, 0) << bare.err;
  const AppResult file = run_binary(
      HMT_PARTITION_BIN, "--config config/default.ini " + args + "--out '" + dir_ + "/file'", dir_);
  ASSERT_EQ(file.exit_code, 0) << file.err;
  for (const char* name : {"topology.json", "config_effective.ini"}) {
    SCOPED_TRACE(name);
    const std::string a = slurp(dir_ + "/bare/" + name);
    EXPECT_FALSE(a.empty());
    EXPECT_EQ(a, slurp(dir_ + "/file/" + name));
  }
  // The same groups of the same log, named from the built-in defaults'
  // folder in one and from config/ in the other.
  auto groups = nlohmann::json::parse(slurp(dir_ + "/bare/groups.json"));
  auto groups_file = nlohmann::json::parse(slurp(dir_ + "/file/groups.json"));
  EXPECT_EQ(fs::weakly_canonical(groups["input"].get<std::string>()),
            fs::weakly_canonical(fs::path(HMT_SOURCE_DIR) / groups_file["input"].get<std::string>()));
  groups.erase("input");
  groups_file.erase("input");
  EXPECT_EQ(groups, groups_file);
  EXPECT_GE(groups["groups"].size(), 2u);
  const AppResult version = run_binary(HMT_PARTITION_BIN, "--version", dir_);
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_EQ(version.out.rfind(std::string("hmt-partition ") + HMT_VERSION_TEXT, 0), 0u)
      << version.out;
}

// [scan_matcher] max_range = auto follows the log's ranges: 20 m for an
// indoor log, the band where the returns are for one whose walls stand far
// off; a number fixes it.
TEST_F(ConfigDefaults, TheMatchingRangeFollowsTheLogsRanges) {
  // A robot creeping across a 100 x 100 m yard: its 181 beams hit the
  // yard's walls 40-70 m away.
  const std::string yard = dir_ + "/yard.log";
  {
    std::ofstream f(yard);
    for (int k = 0; k < 40; ++k) {
      const double x = 0.2 * k;
      f << "FLASER 181";
      for (int i = 0; i < 181; ++i) {
        const double a = (i - 90) * M_PI / 180.0;
        const double c = std::cos(a), s = std::sin(a);
        double r = 1e9;
        if (c > 1e-9) r = std::min(r, (50.0 - x) / c);
        if (s > 1e-9) r = std::min(r, 50.0 / s);
        if (s < -1e-9) r = std::min(r, -50.0 / s);
        f << ' ' << std::min(r, 81.9);
      }
      f << ' ' << x << " 0 0 " << x << " 0 0 " << 1.0 + k << " sim " << 1.0 + k << "\n";
    }
  }
  const auto range_of = [&](const std::string& input, const std::string& sets,
                            const std::string& out) {
    const AppResult r = run_app("run --quiet --input '" + input + "' --set output.png=false " +
                                    sets + " --out '" + dir_ + "/" + out + "'",
                                dir_);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(slurp(dir_ + "/" + out + "/summary.json"));
    return std::make_pair(j.at("matching_range_m").get<double>(), r.err);
  };
  const auto [far, far_err] = range_of(yard, "", "yard");
  EXPECT_GT(far, 45.0);
  EXPECT_LT(far, 72.0);
  EXPECT_NE(far_err.find("[scan_matcher] max_range = auto: " + std::to_string(static_cast<int>(far)) +
                         " m"),
            std::string::npos)
      << far_err;
  const auto [fixed, fixed_err] = range_of(yard, "--set scan_matcher.max_range=20", "fixed");
  EXPECT_EQ(fixed, 20.0);
  EXPECT_EQ(fixed_err.find("max_range = auto"), std::string::npos) << fixed_err;
  const auto [indoor, indoor_err] =
      range_of("datasets/edmonton.log.gz", "--set input.max_steps=30", "indoor");
  EXPECT_EQ(indoor, 20.0) << indoor_err;
}

TEST_F(ConfigDefaults, FilesAndSetsLayerOnTheDefaults) {
  std::ofstream(dir_ + "/a.ini") << "[metric_slam]\nparticles = 7\nseed = 5\n";
  std::ofstream(dir_ + "/b.ini") << "[metric_slam]\nseed = 6\n";
  const AppResult r = run_app("config --dump --config '" + dir_ + "/a.ini' --config '" + dir_ +
                                  "/b.ini' --set grid.resolution=0.1",
                              dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("particles = 7\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("seed = 6\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("resolution = 0.10000000000000001\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("likelihood_gain = 30\n"), std::string::npos) << r.out;  // default
}

TEST_F(ConfigDefaults, UnknownKeyInALayerIsStillAnError) {
  std::ofstream(dir_ + "/typo.ini") << "[grid]\nresolutoin = 0.1\n";
  const std::string typo = " --config '" + dir_ + "/typo.ini'";
  for (const std::string& cmd :
       {"config --dump" + typo,
        "run --quiet --input datasets/edmonton.log.gz" + typo + " --out '" + dir_ + "/o'"}) {
    SCOPED_TRACE(cmd);
    const AppResult r = run_app(cmd, dir_);
    EXPECT_EQ(r.exit_code, static_cast<int>(ExitCode::kConfig)) << r.err;
    EXPECT_NE(r.err.find("typo.ini:2"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("resolutoin"), std::string::npos) << r.err;
  }
  EXPECT_FALSE(fs::exists(dir_ + "/o"));
}

TEST_F(ConfigDefaults, VersionNamesTheProgramAndVersion) {
  const AppResult r = run_app("--version", dir_);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.rfind(std::string("hmt-slam ") + HMT_VERSION_TEXT, 0), 0u) << r.out;
}

}  // namespace
}  // namespace hmt::e2e

// Every shipped configuration file must load: all keys known, all values valid.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "hmt/common/config.h"
#include "hmt/common/error.h"
#include "hmt/pipeline/metric_job.h"

namespace hmt::pipeline {
namespace {
namespace fs = std::filesystem;

// Logs inside the repository must be there; the larger benchmark logs are
// read from the shared datasets beside it, when a machine has them.
bool log_expected(const fs::path& log) {
  const fs::path repo = fs::weakly_canonical(HMT_SOURCE_DIR);
  const std::string rel = fs::weakly_canonical(log).lexically_relative(repo).string();
  const bool in_repo = !rel.empty() && rel.rfind("..", 0) != 0;
  return in_repo || fs::exists(repo.parent_path() / "shared" / "datasets");
}

TEST(ConfigFiles, EveryShippedConfigLoads) {
  const fs::path dir = fs::path(HMT_SOURCE_DIR) / "config";
  int count = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() != ".ini") continue;
    SCOPED_TRACE(e.path().string());
    Config cfg = Config::from_file(e.path().string());
    JobOptions o;
    EXPECT_NO_THROW(o = load_job_options(cfg, dir.string()));
    EXPECT_FALSE(o.input.log.empty());
    if (log_expected(o.input.log)) {
      EXPECT_TRUE(fs::exists(o.input.log)) << o.input.log;
    }
    ++count;
  }
  EXPECT_GE(count, 6);
}

// Each classic CARMEN log of the benchmarks has a configuration of its own
// (config/NAME.ini) that reads that log.
TEST(ConfigFiles, EveryBenchmarkLogHasItsConfig) {
  for (const std::string name : {"edmonton", "intel", "aces", "acapulco", "infinite-corridor"}) {
    const fs::path file = fs::path(HMT_SOURCE_DIR) / "config" / (name + ".ini");
    SCOPED_TRACE(file.string());
    ASSERT_TRUE(fs::exists(file));
    Config cfg = Config::from_file(file.string());
    const JobOptions o = load_job_options(cfg, file.parent_path().string());
    EXPECT_EQ(fs::path(o.input.log).filename().string(), name + ".log.gz");
  }
}

TEST(ConfigFiles, TypoInAKeyIsRejected) {
  Config cfg = Config::from_string("[metric_slam]\nparticels = 30\n", "typo.ini");
  try {
    load_job_options(cfg, "");
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("particels"), std::string::npos);
  }
}

TEST(ConfigFiles, OutOfRangeValueIsRejected) {
  Config cfg = Config::from_string("[metric_slam]\nparticles = 0\n", "bad.ini");
  EXPECT_THROW(load_job_options(cfg, ""), ConfigError);
}

// TSBI's floor on the points a match explains is a share of them: (0, 1].
TEST(ConfigFiles, PointsExplainedOutsideZeroToOneIsRejected) {
  for (const char* value : {"0", "1.5", "-0.2", "nan", "half"}) {
    SCOPED_TRACE(value);
    Config cfg = Config::from_string(
        std::string("[tsbi]\nmin_points_explained = ") + value + "\n", "bad.ini");
    try {
      load_job_options(cfg, "");
      FAIL() << "expected ConfigError";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("min_points_explained"), std::string::npos);
    }
  }
}

// A matcher threshold the clamped log-odds never reach (or one past the
// grid's byte) would leave every scan unmatched: an error, not a bad map.
TEST(ConfigFiles, UnreachableObstacleThresholdIsRejected) {
  for (const char* text : {"[scan_matcher]\noccupied_probability = 0.98\n",
                           "[scan_matcher]\noccupied_probability = 0.999\n",
                           "[grid]\np_clamp = 0.9\n[scan_matcher]\noccupied_probability = 0.9\n"}) {
    SCOPED_TRACE(text);
    Config cfg = Config::from_string(text, "bad.ini");
    try {
      load_job_options(cfg, "");
      FAIL() << "expected ConfigError";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("occupied_probability"), std::string::npos) << e.what();
    }
  }
  Config ok = Config::from_string(
      "[grid]\np_clamp = 0.99\n[scan_matcher]\noccupied_probability = 0.98\n", "ok.ini");
  EXPECT_NO_THROW(load_job_options(ok, ""));
}

}  // namespace
}  // namespace hmt::pipeline

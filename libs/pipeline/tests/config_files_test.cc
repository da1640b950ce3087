// Every shipped configuration file must load: all keys known, all values valid.
#include <gtest/gtest.h>

#include <filesystem>

#include "hmt/common/config.h"
#include "hmt/common/error.h"
#include "hmt/pipeline/metric_job.h"

namespace hmt::pipeline {
namespace {
namespace fs = std::filesystem;

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
    EXPECT_TRUE(fs::exists(o.input.log)) << o.input.log;
    ++count;
  }
  EXPECT_GE(count, 2);
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

}  // namespace
}  // namespace hmt::pipeline

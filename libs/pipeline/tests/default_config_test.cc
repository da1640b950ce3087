// The built-in defaults are config/default.ini, and the command line layers
// files and --set on them with every key still checked.
#include "hmt/pipeline/default_config.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "hmt/common/error.h"
#include "hmt/pipeline/metric_job.h"
#include "hmt_test/scratch.h"

namespace hmt::pipeline {
namespace {
namespace fs = std::filesystem;

using Values = std::map<std::string, std::map<std::string, std::string>>;

const std::string kDefaultIni = std::string(HMT_SOURCE_DIR) + "/config/default.ini";

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// The test's folder for temporary INI files, removed if the test passes.
struct TempDir {
  fs::path dir;
  TempDir() {
    dir = scratch::folder(std::string("default_config_") +
                          ::testing::UnitTest::GetInstance()->current_test_info()->name());
  }
  std::string write(const std::string& name, const std::string& text) const {
    const fs::path p = dir / name;
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }
};

TEST(DefaultConfig, EmbeddedTextIsConfigDefaultIni) {
  const std::string file = slurp(kDefaultIni);
  ASSERT_GT(file.size(), 1000u);
  EXPECT_EQ(default_config_text(), file);
}

TEST(DefaultConfig, EmbeddedAndFileAgreeKeyByKey) {
  const Values embedded = Config::from_string(default_config_text(), "embedded").values();
  const Values file = Config::from_file(kDefaultIni).values();
  ASSERT_GE(file.size(), 12u);  // [input] ... [global_map]
  size_t keys = 0;
  for (const auto& [section, entries] : file) {
    ASSERT_TRUE(embedded.count(section)) << "[" << section << "]";
    for (const auto& [key, value] : entries) {
      ++keys;
      const auto& e = embedded.at(section);
      ASSERT_TRUE(e.count(key)) << "[" << section << "] " << key;
      EXPECT_EQ(e.at(key), value) << "[" << section << "] " << key;
    }
    EXPECT_EQ(embedded.at(section).size(), entries.size()) << "[" << section << "]";
  }
  EXPECT_EQ(embedded.size(), file.size());
  EXPECT_GT(keys, 140u);  // 147 when written
}

// The defaults each component falls back on in code (an empty
// configuration, as `convert` reads a bag's keys) are default.ini's too.
TEST(DefaultConfig, CodeDefaultsAreTheFilesValues) {
  Config empty;
  load_job_options(empty, "");
  const Values code = Config::from_string(empty.effective_ini(), "effective").values();
  const Values file = Config::from_file(kDefaultIni).values();
  for (const auto& [section, entries] : file)
    for (const auto& [key, value] : entries) {
      SCOPED_TRACE("[" + section + "] " + key);
      // The code has no log; the file names the embedded Malaga log.
      if (section == "input" && key == "log") continue;
      ASSERT_TRUE(code.count(section) && code.at(section).count(key));
      const std::string& c = code.at(section).at(key);
      char* end_c = nullptr;
      char* end_f = nullptr;
      const double vc = std::strtod(c.c_str(), &end_c);
      const double vf = std::strtod(value.c_str(), &end_f);
      if (!c.empty() && !value.empty() && *end_c == '\0' && *end_f == '\0')
        EXPECT_DOUBLE_EQ(vc, vf) << c << " vs " << value;
      else
        EXPECT_EQ(c, value);
    }
}

TEST(DefaultConfig, DefaultsAloneLoadAndNameTheEmbeddedLog) {
  Config cfg = layered_config({}, {});
  const JobOptions o = load_job_options(cfg, "");
  EXPECT_EQ(fs::weakly_canonical(o.input.log),
            fs::weakly_canonical(fs::path(HMT_SOURCE_DIR) / "datasets/malaga_one_loop.rawlog"));
  EXPECT_TRUE(fs::exists(o.input.log));
  EXPECT_EQ(o.rbpf.particles, 30);
}

TEST(DefaultConfig, FilesThenSetsLayerOnTheDefaults) {
  TempDir t;
  const std::string a = t.write("a.ini", "[metric_slam]\nparticles = 12\nseed = 7\n"
                                         "[input]\nlog = some.log\n");
  const std::string b = t.write("b.ini", "[metric_slam]\nseed = 9\n");
  Config cfg = layered_config({a, b}, {"metric_slam.threads=2"});
  const JobOptions o = load_job_options(cfg, "");
  EXPECT_EQ(o.rbpf.particles, 12);  // a.ini
  EXPECT_EQ(o.rbpf.seed, 9u);       // b.ini over a.ini
  EXPECT_EQ(o.rbpf.threads, 2);     // --set
  EXPECT_DOUBLE_EQ(o.rbpf.resample_threshold, 0.5);  // the defaults
  EXPECT_EQ(fs::path(o.input.log), t.dir / "some.log");  // from a.ini's folder
  Config over = layered_config({a}, {"metric_slam.particles=5"});
  EXPECT_EQ(load_job_options(over, "").rbpf.particles, 5);
}

TEST(DefaultConfig, UnknownKeyOfAFileIsStillAnErrorNamingIt) {
  TempDir t;
  const std::string f = t.write("typo.ini", "[metric_slam]\nparticels = 12\n");
  Config cfg = layered_config({f}, {});
  try {
    load_job_options(cfg, "");
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("particels"), std::string::npos) << m;
    EXPECT_NE(m.find("typo.ini:2"), std::string::npos) << m;
  }
  Config set = layered_config({}, {"grid.resolutoin=0.1"});
  try {
    load_job_options(set, "");
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("--set grid.resolutoin=0.1"), std::string::npos)
        << e.what();
  }
}

TEST(DefaultConfig, MalformedOrMissingFileIsAnError) {
  TempDir t;
  const std::string bad = t.write("bad.ini", "[grid]\nresolution 0.1\n");
  try {
    layered_config({bad}, {});
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.ini:2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(layered_config({(t.dir / "absent.ini").string()}, {}), ConfigError);
  EXPECT_THROW(layered_config({}, {"no_dot_here"}), ConfigError);
  // A bad value given by a layer is an error naming that layer.
  Config v = layered_config({}, {"metric_slam.particles=many"});
  EXPECT_THROW(load_job_options(v, ""), ConfigError);
}

}  // namespace
}  // namespace hmt::pipeline

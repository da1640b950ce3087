// The hmt-experiments executable with few runs: exit codes, and that every
// output file is written and consistent with the options.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "hmt_test/scratch.h"

namespace {

namespace fs = std::filesystem;

int run(const std::string& args) {
  const std::string cmd = std::string(HMT_EXPERIMENTS_BIN) + " " + args + " >/dev/null 2>&1";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::vector<std::string> lines(const fs::path& p) {
  std::ifstream f(p);
  std::vector<std::string> out;
  for (std::string l; std::getline(f, l);) out.push_back(l);
  return out;
}

// The folder the test's run writes, removed if the test passes.
fs::path temp_dir(const std::string& name) {
  const fs::path d = hmt::scratch::track(fs::temp_directory_path() /
                                         ("hmt_experiments_" + name + "_" +
                                          std::to_string(::getpid())));
  fs::remove_all(d);
  return d;
}

TEST(experiments_App, InfoLossWithFewRuns) {
  const fs::path d = temp_dir("info");
  ASSERT_EQ(run("info-loss --runs 3 --threads 2 --k-max 6 --taus 0.1,0.2 --quiet --out " +
                d.string()),
            0);
  // Per run: the main spectral row, the even control, 2 taus, k = 2..6.
  const auto runs = lines(d / "info_loss_runs.csv");
  ASSERT_EQ(runs.size(), 1u + 3u * (1 + 1 + 2 + 5));
  EXPECT_EQ(runs[0], "run,method,param,groups,e");
  const auto summary = lines(d / "info_loss_summary.csv");
  ASSERT_EQ(summary.size(), 1u + 1 + 1 + 2 + 5);
  std::ifstream ex(d / "info_loss_example.json");
  const auto j = nlohmann::json::parse(ex);
  EXPECT_EQ(j["steps"].size(), 251u);
  EXPECT_EQ(j["landmarks_true"].size(), 60u);
  std::ifstream meta(d / "info_loss.json");
  const auto m = nlohmann::json::parse(meta);
  EXPECT_EQ(m["options"]["runs"], 3);
  EXPECT_EQ(m["summary"].size(), summary.size() - 1);
  for (const auto& row : m["summary"]) {
    EXPECT_GE(row["e"]["min"].get<double>(), 0.0);
    EXPECT_LT(row["e"]["max"].get<double>(), 1.0);
  }
}

TEST(experiments_App, FieldOfViewOnTheSmallWorld) {
  const fs::path d = temp_dir("fov");
  ASSERT_EQ(run("field-of-view --world two-rooms --taus 0.5,1 --out " + d.string()), 0);
  const auto rows = lines(d / "field_of_view.csv");
  ASSERT_EQ(rows.size(), 1u + 3 * 2);
  std::ifstream f(d / "field_of_view.json");
  const auto j = nlohmann::json::parse(f);
  ASSERT_EQ(j["results"].size(), 6u);
  for (const auto& r : j["results"])
    EXPECT_EQ(r["labels"].size(), j["poses"].size());
}

TEST(experiments_App, BadArgumentsAreUsageErrors) {
  const fs::path d = temp_dir("bad");
  EXPECT_EQ(run("info-loss --runs 0 --out " + d.string()), 2);
  EXPECT_EQ(run("info-loss --runs 1 --information full --out " + d.string()), 2);
  EXPECT_EQ(run("info-loss --runs 1 --taus 0.1,3 --out " + d.string()), 2);
  EXPECT_EQ(run("info-loss --runs 1 --split-method median --out " + d.string()), 2);
  EXPECT_EQ(run("field-of-view --world castle --out " + d.string()), 2);
  EXPECT_EQ(run("field-of-view --taus -1 --out " + d.string()), 2);
  EXPECT_EQ(run("nonsense"), 2);
  EXPECT_FALSE(fs::exists(d / "info_loss_runs.csv"));
}

}  // namespace

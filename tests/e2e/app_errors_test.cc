// Bad input through the application: each case ends with one clear error line
// on stderr and its own non-zero exit code, never a crash or a hang.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "hmt/common/error.h"
#include "hmt/common/random.h"
#include "run_app.h"

namespace hmt::e2e {
namespace {
namespace fs = std::filesystem;

std::string last_line(const std::string& s) {
  std::string t = s;
  while (!t.empty() && t.back() == '\n') t.pop_back();
  const auto p = t.rfind('\n');
  return p == std::string::npos ? t : t.substr(p + 1);
}

void expect_error(const AppResult& r, ExitCode code, const std::string& mention) {
  EXPECT_EQ(r.exit_code, static_cast<int>(code)) << r.err;
  const std::string line = last_line(r.err);
  EXPECT_EQ(line.rfind("hmt-slam: error: ", 0), 0u) << r.err;
  EXPECT_NE(line.find(mention), std::string::npos) << line;
}

void write(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

std::string carmen_line(const std::string& ranges, int n) {
  return "FLASER " + std::to_string(n) + " " + ranges + " 0 0 0 0 0 0 1.0 host 1.0\n";
}

std::string ranges(int n, const std::string& v) {
  std::string s;
  for (int i = 0; i < n; ++i) s += (i ? " " : "") + v;
  return s;
}

class AppErrors : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = temp_dir(::testing::UnitTest::GetInstance()->current_test_info()->name()); }
  AppResult run_input(const std::string& log) {
    return run_app("run --config config/default.ini --quiet --input '" + log + "' --out '" +
                       dir_ + "/out'", dir_);
  }
  std::string dir_;
};

TEST_F(AppErrors, MissingInputFile) {
  expect_error(run_input(dir_ + "/nope.rawlog"), ExitCode::kInput, "nope.rawlog");
}

TEST_F(AppErrors, RandomBytes) {
  Random rng(3);
  std::string junk;
  for (int i = 0; i < 5000; ++i) junk.push_back(static_cast<char>(rng.next_u64() & 0xff));
  write(dir_ + "/junk.rawlog", junk);
  expect_error(run_input(dir_ + "/junk.rawlog"), ExitCode::kInput, "junk.rawlog");
}

TEST_F(AppErrors, TruncatedGzip) {
  const std::string full = slurp(std::string(HMT_SOURCE_DIR) + "/datasets/edmonton.log.gz");
  write(dir_ + "/cut.log.gz", full.substr(0, full.size() / 2));
  expect_error(run_input(dir_ + "/cut.log.gz"), ExitCode::kInput, "cut.log.gz");
}

TEST_F(AppErrors, CarmenWrongFieldCount) {
  write(dir_ + "/short.log", carmen_line(ranges(170, "1.0"), 180));
  expect_error(run_input(dir_ + "/short.log"), ExitCode::kInput, "line 1");
}

TEST_F(AppErrors, NanRange) {
  write(dir_ + "/nan.log", carmen_line(ranges(90, "1.0") + " nan " + ranges(89, "1.0"), 180));
  expect_error(run_input(dir_ + "/nan.log"), ExitCode::kInput, "line 1");
}

TEST_F(AppErrors, NegativeRange) {
  write(dir_ + "/neg.log", carmen_line(ranges(90, "1.0") + " -2.0 " + ranges(89, "1.0"), 180));
  expect_error(run_input(dir_ + "/neg.log"), ExitCode::kInput, "line 1");
}

TEST_F(AppErrors, ZeroBeamScan) {
  write(dir_ + "/zero.log", "FLASER 0 0 0 0 0 0 0 1.0 host 1.0\n");
  expect_error(run_input(dir_ + "/zero.log"), ExitCode::kInput, "line 1");
}

TEST_F(AppErrors, EmptyLog) {
  write(dir_ + "/empty.log", "");
  expect_error(run_input(dir_ + "/empty.log"), ExitCode::kInput, "empty.log");
}

TEST_F(AppErrors, UnknownConfigKeyInFile) {
  write(dir_ + "/typo.ini", "[metric_slam]\nparticels = 30\n");
  const AppResult r = run_app("run --config '" + dir_ + "/typo.ini' --input datasets/edmonton.log.gz --out '" + dir_ + "/o'", dir_);
  expect_error(r, ExitCode::kConfig, "particels");
  EXPECT_NE(last_line(r.err).find("typo.ini"), std::string::npos);
}

TEST_F(AppErrors, MalformedConfigValue) {
  write(dir_ + "/bad.ini", "[grid]\nresolution = 5cm\n");
  expect_error(run_app("run --config '" + dir_ + "/bad.ini' --out '" + dir_ + "/o'", dir_),
               ExitCode::kConfig, "resolution");
}

TEST_F(AppErrors, OutOfRangeConfigValue) {
  expect_error(run_app("run --config config/default.ini --set grid.resolution=-1 --out '" + dir_ + "/o'", dir_),
               ExitCode::kConfig, "resolution");
}

TEST_F(AppErrors, MalformedOverride) {
  expect_error(run_app("run --config config/default.ini --set particles30 --out '" + dir_ + "/o'", dir_),
               ExitCode::kConfig, "particles30");
}

TEST_F(AppErrors, UnknownOverrideKey) {
  expect_error(run_app("run --config config/default.ini --set metric_slam.particels=3 --out '" + dir_ + "/o'", dir_),
               ExitCode::kConfig, "particels");
}

TEST_F(AppErrors, MissingConfigFile) {
  expect_error(run_app("run --config '" + dir_ + "/none.ini'", dir_), ExitCode::kConfig, "none.ini");
}

TEST_F(AppErrors, BadCommandLine) {
  EXPECT_EQ(run_app("", dir_).exit_code, static_cast<int>(ExitCode::kUsage));
  EXPECT_EQ(run_app("run --bogus", dir_).exit_code, static_cast<int>(ExitCode::kUsage));
  expect_error(run_app("convert --input datasets/edmonton.log.gz --output '" + dir_ +
                           "/x.rawlog' --format xml", dir_),
               ExitCode::kUsage, "xml");
}

TEST_F(AppErrors, UnwritableOutput) {
  write(dir_ + "/file", "not a folder");
  expect_error(run_app("run --config config/default.ini --quiet --set input.max_steps=3 --out '" +
                           dir_ + "/file/out'", dir_),
               ExitCode::kOutput, "file/out");
}

TEST_F(AppErrors, FailedRunLeavesEarlierOutputsIntact) {
  const AppResult ok = run_app("run --config config/default.ini --quiet --set input.max_steps=20 --out '" +
                                   dir_ + "/out'", dir_);
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  const std::string png = slurp(dir_ + "/out/map.png"), tum = slurp(dir_ + "/out/trajectory.tum");
  write(dir_ + "/short.log", carmen_line(ranges(10, "1.0"), 180));
  expect_error(run_input(dir_ + "/short.log"), ExitCode::kInput, "short.log");
  EXPECT_EQ(slurp(dir_ + "/out/map.png"), png);
  EXPECT_EQ(slurp(dir_ + "/out/trajectory.tum"), tum);
  for (const auto& e : fs::directory_iterator(dir_ + "/out"))
    EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << e.path();
}

}  // namespace
}  // namespace hmt::e2e

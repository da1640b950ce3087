// Checkpoints through the application (issue 15 item 2): a run killed with
// SIGKILL at random moments — in the middle of a scan, of a checkpoint
// write, of start-up — and resumed from its last checkpoint each time ends
// with the same output bytes as a run never interrupted; SIGINT stops a run
// with a clear message and a checkpoint that resumes it.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "run_app.h"

namespace hmt::e2e {
namespace {
namespace fs = std::filesystem;

// The outputs an uninterrupted run and a resumed one must share byte for
// byte (the timings of summary.json, memory.csv and process_times.csv are
// measurements, not results).
const char* const kResults[] = {"trajectory.tum",     "map.png",           "map.pgm",
                                "map.yaml",           "map_topology.png",  "hmt_map.bin",
                                "topology.json",      "topology.dot",      "tsbi_events.csv",
                                "tsbi_candidates.csv",
                                "topological_pmf.csv", "ess.csv",          "config_effective.ini",
                                "areas/area_1.png"};

// hmt-slam started with `args` (no shell between, so a signal reaches it),
// from the source folder, its output appended to `log`.
pid_t spawn(const std::vector<std::string>& args, const std::string& log) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    if (::chdir(HMT_SOURCE_DIR) != 0) ::_exit(127);
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    const int null = ::open("/dev/null", O_RDONLY);
    if (fd < 0 || null < 0) ::_exit(127);
    ::dup2(null, 0);
    ::dup2(fd, 1);
    ::dup2(fd, 2);
    std::vector<char*> argv;
    static std::string bin = HMT_SLAM_BIN;
    argv.push_back(bin.data());
    std::vector<std::string> copy = args;
    for (std::string& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(bin.c_str(), argv.data());
    ::_exit(127);
  }
  return pid;
}

// Waits up to `ms`; true and the exit status if the process ended.
bool wait_for(pid_t pid, int ms, int* status) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
  while (std::chrono::steady_clock::now() < until) {
    if (::waitpid(pid, status, WNOHANG) == pid) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

std::vector<std::string> run_args(const std::string& out) {
  return {"run", "--quiet", "--set", "output.checkpoint_every=8", "--out", out};
}

// summary.json's counts of the metric filter: results, which a checkpoint
// carries over, unlike its timings.
nlohmann::json metric_counts(const std::string& out) {
  return nlohmann::json::parse(slurp(out + "/summary.json")).at("metric_slam");
}

TEST(Checkpoint, KilledAtRandomMomentsAndResumedEndsWithTheSameBytes) {
  const std::string dir = temp_dir("checkpoint_kill");
  // The reference: the embedded Malaga log (its loop closed) without a stop,
  // timed: the kills below come at random fractions of its duration, so
  // that a fast machine (or a slow sanitizer build) kills as often.
  double whole_ms = 0.0;
  {
    int status = 0;
    const auto t0 = std::chrono::steady_clock::now();
    const pid_t pid = spawn(run_args(dir + "/whole"), dir + "/whole.log");
    ASSERT_TRUE(wait_for(pid, 600000, &status));
    whole_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                   .count();
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << slurp(dir + "/whole.log");
  }
  EXPECT_FALSE(fs::exists(dir + "/whole/checkpoint.bin")) << "a finished run keeps no checkpoint";

  // The same run, killed after a random delay again and again: each time
  // resumed from the checkpoint if there is one, started over if not.
  const std::string out = dir + "/killed", ckpt = out + "/checkpoint.bin";
  std::mt19937 rng(20261125);
  // Each attempt runs for 2-20 % of the whole run: from before its first
  // checkpoint to well past it, and short enough that a dozen attempts do
  // not finish the log (a resumed one starts from the last checkpoint).
  std::uniform_real_distribution<double> fraction(0.02, 0.2);
  auto delay_ms = [&] { return 1 + static_cast<int>(fraction(rng) * whole_ms); };
  int kills = 0, resumes = 0;
  bool done = false;
  for (int attempt = 0; attempt < 60 && !done; ++attempt) {
    const bool resume = fs::exists(ckpt);
    resumes += resume ? 1 : 0;
    const pid_t pid =
        spawn(resume ? std::vector<std::string>{"resume", "--quiet", "--checkpoint", ckpt}
                     : run_args(out),
              dir + "/killed.log");
    int status = 0;
    // After 12 kills the run is left to finish.
    const bool ended = wait_for(pid, kills < 12 ? delay_ms() : 600000, &status);
    if (!ended && kills < 12) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      ++kills;
      continue;
    }
    ASSERT_TRUE(ended) << "attempt " << attempt << " did not end";
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
        << "attempt " << attempt << ":\n" << slurp(dir + "/killed.log");
    done = true;
  }
  ASSERT_TRUE(done);
  // The test did what it says: killed runs, and resumed from checkpoints.
  EXPECT_GE(kills, 6);
  EXPECT_GE(resumes, 3);
  for (const char* f : kResults)
    EXPECT_TRUE(slurp(dir + "/whole/" + f) == slurp(out + "/" + f)) << f << " differs";
  EXPECT_EQ(metric_counts(dir + "/whole"), metric_counts(out));
  EXPECT_FALSE(fs::exists(ckpt));
  // No temporary file of an interrupted write is left in a finished folder.
  for (const auto& e : fs::directory_iterator(out))
    EXPECT_EQ(e.path().filename().string().find(".tmp."), std::string::npos) << e.path();
}

TEST(Checkpoint, SigintStopsWithAClearMessageAndAResumableCheckpoint) {
  const std::string dir = temp_dir("checkpoint_sigint");
  const std::vector<std::string> args = {"run", "--quiet", "--out", dir + "/out"};
  int status = 0;
  {
    const pid_t pid = spawn(args, dir + "/whole.log");
    ASSERT_TRUE(wait_for(pid, 600000, &status));
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << slurp(dir + "/whole.log");
    fs::rename(dir + "/out", dir + "/whole");
  }
  // Interrupted once its first scans are done (checkpoint_every = 0: the
  // signal alone makes the checkpoint).
  const pid_t pid = spawn(args, dir + "/stopped.log");
  for (int i = 0; i < 2000 && !fs::exists(dir + "/out/config_effective.ini"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  std::this_thread::sleep_for(std::chrono::milliseconds(600));
  ::kill(pid, SIGINT);
  ASSERT_TRUE(wait_for(pid, 600000, &status));
  const std::string said = slurp(dir + "/stopped.log");
  ASSERT_TRUE(WIFEXITED(status)) << said;
  if (WEXITSTATUS(status) == 0) GTEST_SKIP() << "the run ended before the signal came";
  EXPECT_EQ(WEXITSTATUS(status), 130) << said;
  EXPECT_NE(said.find("stopped by SIGINT after scan"), std::string::npos) << said;
  EXPECT_NE(said.find("hmt-slam resume --checkpoint " + dir + "/out/checkpoint.bin"),
            std::string::npos)
      << said;
  EXPECT_EQ(said.find("error"), std::string::npos) << said;
  ASSERT_TRUE(fs::exists(dir + "/out/checkpoint.bin"));

  // --config / --set cannot change a checkpointed run.
  const AppResult bad = run_app("resume --quiet --checkpoint '" + dir +
                                    "/out/checkpoint.bin' --set metric_slam.seed=3", dir);
  EXPECT_EQ(bad.exit_code, 2) << bad.err;
  EXPECT_NE(bad.err.find("own configuration"), std::string::npos) << bad.err;
  // Another log than the run's: refused, by name.
  const AppResult other = run_app("resume --quiet --checkpoint '" + dir +
                                      "/out/checkpoint.bin' --input datasets/seattle.log.gz "
                                      "--out '" + dir + "/other'", dir);
  if (fs::exists(std::string(HMT_SOURCE_DIR) + "/datasets/seattle.log.gz")) {
    EXPECT_EQ(other.exit_code, 4) << other.err;
    EXPECT_NE(other.err.find("not the log it was written from"), std::string::npos) << other.err;
  }

  const AppResult r = run_app("resume --quiet --checkpoint '" + dir + "/out/checkpoint.bin'", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* f : kResults)
    EXPECT_TRUE(slurp(dir + "/whole/" + f) == slurp(dir + "/out/" + f)) << f << " differs";
  EXPECT_EQ(metric_counts(dir + "/whole"), metric_counts(dir + "/out"));
}

// A live run cannot be resumed: it says so and writes no checkpoint.
TEST(Checkpoint, LiveModeSaysItWritesNoCheckpoint) {
  const std::string dir = temp_dir("checkpoint_live");
  const AppResult r = run_app("run --quiet --set framework.mode=live --set framework.live_speed=0 "
                              "--set input.max_steps=60 --set output.checkpoint_every=10 --out '" +
                                  dir + "/out'", dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("no checkpoints"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/out/checkpoint.bin"));
}

}  // namespace
}  // namespace hmt::e2e

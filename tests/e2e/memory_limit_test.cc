// Memory exhaustion is an error, not a crash: under an address-space limit
// too small for the run, hmt-slam exits with its internal-error code and a
// message naming the cause, and the outputs an earlier run left in the same
// folder are intact (every output is written to a temporary file and
// renamed).
#include <gtest/gtest.h>

#include <filesystem>
#include <map>

#include "hmt/common/error.h"
#include "run_app.h"

namespace hmt::e2e {
namespace {
namespace fs = std::filesystem;

std::map<std::string, std::string> folder_contents(const std::string& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) files[e.path().string()] = slurp(e.path().string());
  return files;
}

TEST(MemoryLimit, OutOfMemoryIsAClearErrorAndEarlierOutputsStay) {
  if (kSanitizerBuild)
    GTEST_SKIP() << "sanitizer runtimes reserve terabytes of address space: ulimit -v cannot apply";
  const std::string dir = temp_dir("memory_limit");
  const std::string out = dir + "/out";
  // The same command twice, so that what the second run writes before it
  // fails (its config_effective.ini) is what the first one wrote.
  const std::string args =
      "run --config config/default.ini --quiet --set input.max_steps=40 --out '" + out + "'";
  const AppResult first = run_app(args, dir);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const auto before = folder_contents(out);
  ASSERT_FALSE(before.empty());

  // 100 MB of address space: enough to load the program and read the
  // configuration, far too little for the particles' maps and threads.
  const AppResult limited = run_binary("/bin/sh", "-c \"ulimit -v 100000 && exec '" +
                                                      std::string(HMT_SLAM_BIN) + "' " + args +
                                                      "\"",
                                       dir);
  EXPECT_EQ(limited.exit_code, static_cast<int>(ExitCode::kInternal)) << limited.err;
  EXPECT_NE(limited.err.find("hmt-slam: internal error: out of memory"), std::string::npos)
      << limited.err;
  const auto after = folder_contents(out);
  EXPECT_EQ(after.size(), before.size());
  for (const auto& [path, bytes] : before) {
    const auto it = after.find(path);
    EXPECT_TRUE(it != after.end() && it->second == bytes) << path << " was changed or removed";
  }
}

}  // namespace
}  // namespace hmt::e2e

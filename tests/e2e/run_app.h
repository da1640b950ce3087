// Runs the hmt-slam executable as a user would and captures what it says.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "hmt_test/scratch.h"

namespace hmt::e2e {

// Built with AddressSanitizer or ThreadSanitizer, whose runtimes change how
// much memory and address space a process takes.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
inline constexpr bool kSanitizerBuild = true;
#else
inline constexpr bool kSanitizerBuild = false;
#endif

struct AppResult {
  int exit_code = -1;
  std::string out, err;
};

inline std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// A fresh folder for the running test, removed if it passes.
inline std::string temp_dir(const std::string& name) {
  return scratch::folder("e2e_" + name).string();
}

// Runs `binary` with `args` appended as is (quote paths yourself), from the
// source folder, with no standard input.
inline AppResult run_binary(const std::string& binary, const std::string& args,
                            const std::string& work_dir) {
  const std::string out = work_dir + "/stdout.txt", err = work_dir + "/stderr.txt";
  const std::string cmd = std::string("cd '") + HMT_SOURCE_DIR + "' && '" + binary +
                          "' " + args + " </dev/null >'" + out + "' 2>'" + err + "'";
  const int status = std::system(cmd.c_str());
  AppResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

// hmt-slam.
inline AppResult run_app(const std::string& args, const std::string& work_dir) {
  return run_binary(HMT_SLAM_BIN, args, work_dir);
}

}  // namespace hmt::e2e

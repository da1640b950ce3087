// Scratch files and folders of the tests: removed when their test passes,
// kept (and named on the output) when it fails. Without it every run of the
// suites left its folders in the temporary directory; a failure still leaves
// the developer what the test wrote.
//
// hmt::scratch::track(path) registers a path the running test made; one
// registered while no test runs (e.g. in SetUpTestSuite) belongs to the test
// suite and is settled when the suite ends. A gtest listener, installed on the
// first registration, does the removing. A skipped test counts as passed.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace hmt::scratch {

// kIfEmpty: a parent shared by several tests' paths, removed once empty.
enum class Remove { kAll, kIfEmpty };

namespace detail {

struct Entry {
  std::filesystem::path path;
  Remove how;
  bool operator==(const Entry& o) const { return path == o.path && how == o.how; }
};

struct Registry {
  std::mutex mutex;
  std::vector<Entry> test, suite;
};

inline Registry& registry() {
  static Registry r;
  return r;
}

// Removes `entries`, the last registered first, if `passed`; else names them.
inline void settle(std::vector<Entry>& entries, bool passed) {
  namespace fs = std::filesystem;
  for (auto it = entries.rbegin(); it != entries.rend(); ++it) {
    std::error_code ec;
    if (passed && it->how == Remove::kAll) {
      fs::remove_all(it->path, ec);
    } else if (passed) {
      fs::remove(it->path, ec);  // fails, and keeps it, unless it is empty
    } else if (it->how == Remove::kAll && fs::exists(it->path, ec)) {
      std::printf("kept scratch %s: %s\n", fs::is_directory(it->path, ec) ? "folder" : "file",
                  it->path.c_str());
    }
  }
  std::fflush(stdout);
  entries.clear();
}

class Listener : public ::testing::EmptyTestEventListener {
  void OnTestEnd(const ::testing::TestInfo& info) override {
    std::lock_guard<std::mutex> lock(registry().mutex);
    settle(registry().test, !info.result()->Failed());
  }
  void OnTestSuiteEnd(const ::testing::TestSuite& suite) override {
    std::lock_guard<std::mutex> lock(registry().mutex);
    settle(registry().suite, !suite.Failed());
  }
};

}  // namespace detail

// Registers `path` (file or folder, made or about to be) and returns it.
inline std::filesystem::path track(std::filesystem::path path, Remove how = Remove::kAll) {
  detail::Registry& r = detail::registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  static bool installed = false;
  if (!installed) {
    ::testing::UnitTest::GetInstance()->listeners().Append(new detail::Listener);
    installed = true;
  }
  std::vector<detail::Entry>& entries =
      ::testing::UnitTest::GetInstance()->current_test_info() ? r.test : r.suite;
  const detail::Entry e{std::move(path), how};
  if (std::find(entries.begin(), entries.end(), e) == entries.end()) entries.push_back(e);
  return e.path;
}

// A fresh, empty folder `hmt_<name>_<pid>` in the temporary directory for the
// running test, registered (the pid keeps two suites run at once apart).
inline std::filesystem::path folder(const std::string& name) {
  const std::filesystem::path d = track(std::filesystem::temp_directory_path() /
                                        ("hmt_" + name + "_" + std::to_string(::getpid())));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

}  // namespace hmt::scratch

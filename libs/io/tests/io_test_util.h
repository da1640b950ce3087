// Shared helpers of the hmt_io tests: data paths, scratch files, and a check
// that a call fails with a one-line hmt::InputError saying the right thing.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>
#include <zlib.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <iterator>
#include <string>

#include "hmt/common/error.h"

namespace hmt::io::testing_util {

inline std::string repo_path(const std::string& rel) {
  return std::string(HMT_SOURCE_DIR) + "/" + rel;
}
// MRPT's sample dataset; gzip-compressed despite its name.
inline std::string malaga_path() {
  return repo_path("datasets/malaga_one_loop.rawlog");
}
inline std::string edmonton_path() {
  return repo_path("datasets/edmonton.log.gz");
}
// The big logs live next to the repository, not in it (see its README).
inline std::string shared_carmen_path(const std::string& name) {
  return repo_path("../shared/datasets/carmen/" + name + ".log.gz");
}

// A fresh folder per test, under gtest's temporary directory.
inline std::string scratch_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string dir = ::testing::TempDir() + "hmt_io_tests_" +
                          std::to_string(::getpid()) + "/" +
                          info->test_suite_name() + "." + info->name();
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

inline void write_bytes(const std::string& path, const std::string& data) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(data.data(), static_cast<std::streamsize>(data.size()));
  ASSERT_TRUE(out.good()) << path;
}

// The decompressed content of a gzip (or plain) file.
inline std::string gunzip_file(const std::string& path) {
  gzFile f = gzopen(path.c_str(), "rb");
  EXPECT_NE(f, nullptr) << path;
  std::string out;
  char buf[1 << 16];
  int got;
  while (f && (got = gzread(f, buf, sizeof(buf))) > 0)
    out.append(buf, static_cast<size_t>(got));
  if (f) gzclose(f);
  return out;
}

// gzip-compresses `data` in memory (what `gzip -c` would write).
inline std::string gzip_bytes(const std::string& data) {
  z_stream zs{};
  EXPECT_EQ(deflateInit2(&zs, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY),
            Z_OK);
  std::string out(deflateBound(&zs, data.size()) + 64, '\0');
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
  zs.avail_in = static_cast<uInt>(data.size());
  zs.next_out = reinterpret_cast<Bytef*>(out.data());
  zs.avail_out = static_cast<uInt>(out.size());
  EXPECT_EQ(deflate(&zs, Z_FINISH), Z_STREAM_END);
  out.resize(zs.total_out);
  deflateEnd(&zs);
  return out;
}

// Runs `fn`, expecting an hmt::InputError whose one-line message contains
// every one of `parts`.
inline void expect_input_error(const std::function<void()>& fn,
                               std::initializer_list<std::string> parts) {
  try {
    fn();
    ADD_FAILURE() << "no InputError thrown";
  } catch (const hmt::InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "multi-line: " << msg;
    for (const auto& p : parts)
      EXPECT_NE(msg.find(p), std::string::npos)
          << "message lacks '" << p << "': " << msg;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "wrong exception type: " << e.what();
  }
}

}  // namespace hmt::io::testing_util

// Shared helpers of the hmt_io tests: data paths, scratch files, and a check
// that a call fails with a one-line hmt::InputError saying the right thing.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>
#include <zlib.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <iterator>
#include <string>

#include "hmt/common/error.h"
#include "hmt/common/sensor_data.h"
#include "hmt_test/scratch.h"

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

// A fresh folder per test, under gtest's temporary directory, removed if the
// test passes, and the folders above it (the process's; a parameterized
// test's name holds '/'s) once empty.
inline std::string scratch_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::string parent =
      ::testing::TempDir() + "hmt_io_tests_" + std::to_string(::getpid());
  const std::string name =
      std::string(info->test_suite_name()) + "." + info->name();
  const std::string dir = parent + "/" + name;
  hmt::scratch::track(parent, hmt::scratch::Remove::kIfEmpty);
  for (size_t s = name.find('/'); s != std::string::npos; s = name.find('/', s + 1))
    hmt::scratch::track(parent + "/" + name.substr(0, s), hmt::scratch::Remove::kIfEmpty);
  hmt::scratch::track(dir);
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

// A FLASER line of `n` beams with the given readings (repeated), odometry
// (x, 0, 0) and timestamp t.
inline std::string flaser(int n, const std::string& reading, double x, double t) {
  std::string line = "FLASER " + std::to_string(n);
  for (int i = 0; i < n; ++i) line += " " + reading;
  const std::string pose = std::to_string(x) + " 0 0";
  line += " " + pose + " " + pose + " " + std::to_string(t) + " host " +
          std::to_string(t) + "\n";
  return line;
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

// Same bits, not just nearly equal values: the native rawlog reader must
// give exactly what MRPT's deserializers give. Scans that store no time get
// the time they are read at, which two reads can only share to
// `time_tolerance` seconds (0: bit for bit).
template <typename T>
bool same_bits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

inline void expect_identical_logs(const hmt::Log& a, const hmt::Log& b,
                                  double time_tolerance = 0.0) {
  EXPECT_EQ(a.source, b.source);
  ASSERT_EQ(a.steps.size(), b.steps.size());
  for (size_t k = 0; k < a.steps.size(); ++k) {
    SCOPED_TRACE("step " + std::to_string(k));
    const LogStep& x = a.steps[k];
    const LogStep& y = b.steps[k];
    if (time_tolerance > 0.0) {
      EXPECT_NEAR(x.timestamp, y.timestamp, time_tolerance);
      EXPECT_NEAR(x.scan.timestamp, y.scan.timestamp, time_tolerance);
    } else {
      EXPECT_TRUE(same_bits(x.timestamp, y.timestamp));
      EXPECT_TRUE(same_bits(x.scan.timestamp, y.scan.timestamp));
    }
    EXPECT_EQ(x.has_odometry, y.has_odometry);
    EXPECT_TRUE(same_bits(x.odometry_increment.x, y.odometry_increment.x));
    EXPECT_TRUE(same_bits(x.odometry_increment.y, y.odometry_increment.y));
    EXPECT_TRUE(
        same_bits(x.odometry_increment.theta, y.odometry_increment.theta));
    const LaserScan& s = x.scan;
    const LaserScan& t = y.scan;
    EXPECT_TRUE(same_bits(s.angle_min, t.angle_min));
    EXPECT_TRUE(same_bits(s.angle_increment, t.angle_increment));
    EXPECT_TRUE(same_bits(s.max_range, t.max_range));
    EXPECT_TRUE(same_bits(s.sensor_pose.x, t.sensor_pose.x));
    EXPECT_TRUE(same_bits(s.sensor_pose.y, t.sensor_pose.y));
    EXPECT_TRUE(same_bits(s.sensor_pose.theta, t.sensor_pose.theta));
    EXPECT_EQ(s.valid, t.valid);
    ASSERT_EQ(s.ranges.size(), t.ranges.size());
    EXPECT_EQ(std::memcmp(s.ranges.data(), t.ranges.data(),
                          s.ranges.size() * sizeof(float)),
              0);
  }
}

}  // namespace hmt::io::testing_util

// The native rawlog reader and writer against MRPT on real logs: the same
// log read, the same bytes written; the MRPT plugin for classes the native
// reader does not know; and damaged files, which must end in an InputError
// naming the file, never a crash.
#include <gtest/gtest.h>

#include <mrpt/obs/CObservationGPS.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <cstdlib>
#include <filesystem>
#include <random>

#include "archive_bytes.h"
#include "hmt/io/carmen.h"
#include "hmt/io/log_reader.h"
#include "hmt/io/rawlog.h"
#include "io_test_util.h"
#include "mrpt_fallback.h"
#include "mrpt_test_util.h"

namespace hmt::io {
namespace {

using namespace testing_util;

// Reads `path` natively (without MRPT) and with MRPT, and compares.
void expect_native_reads_like_mrpt(const std::string& path) {
  SCOPED_TRACE(path);
  const size_t fallbacks = detail::mrpt_fallback_reads();
  const hmt::Log native = read_rawlog(path);
  EXPECT_EQ(detail::mrpt_fallback_reads(), fallbacks) << "read through MRPT";
  const hmt::Log mrpt = detail::read_rawlog_with_mrpt(path, false, "the test");
  expect_identical_logs(native, mrpt);
}

// The CARMEN logs next to the repository (see its README), when present.
std::vector<std::string> shared_carmen_logs() {
  std::vector<std::string> out;
  for (const char* name : {"intel", "aces", "acapulco", "infinite-corridor"})
    if (std::filesystem::exists(shared_carmen_path(name)))
      out.push_back(shared_carmen_path(name));
  return out;
}

constexpr RawlogFormat kFormats[] = {RawlogFormat::kActionsSensoryFrames,
                                     RawlogFormat::kObservationsOnly};

TEST(NativeRawlogReader, MalagaAsMrptReadsIt) {
  expect_native_reads_like_mrpt(malaga_path());  // gzip
  const std::string p = scratch_dir() + "/malaga_plain.rawlog";
  write_bytes(p, gunzip_file(malaga_path()));
  expect_native_reads_like_mrpt(p);
}

// CARMEN logs converted by MRPT: MRPT 2.5.8's own class names and versions.
TEST(NativeRawlogReader, MrptWrittenLogsAsMrptReadsThem) {
  std::vector<std::string> logs = {edmonton_path()};
  for (const auto& p : shared_carmen_logs()) logs.push_back(p);
  const std::string dir = scratch_dir();
  for (const std::string& src : logs) {
    const hmt::Log log = read_carmen(src);
    for (RawlogFormat f : kFormats) {
      const std::string p = dir + "/converted.rawlog";
      write_rawlog_with_mrpt(log, p, f);
      expect_native_reads_like_mrpt(p);
    }
  }
}

// A log exercising the writer's corners: angles near +-pi, asymmetric and
// left-to-right scans, times before 1970.
hmt::Log awkward_log() {
  hmt::Log log;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 200; ++k) {
    LogStep s;
    s.timestamp = -3.0 + 0.1234567 * k;
    s.has_odometry = k > 0;
    if (k > 0)
      s.odometry_increment = Pose2D(u(rng), u(rng), k % 7 == 0 ? M_PI : 3.2 * u(rng));
    s.scan.timestamp = s.timestamp;
    s.scan.angle_min = static_cast<float>(1.6 * u(rng));
    s.scan.angle_increment = static_cast<float>(k % 3 == 0 ? -0.01 : 0.0123);
    s.scan.max_range = 30.0f;
    for (int i = 0; i < 90; ++i) {
      s.scan.ranges.push_back(static_cast<float>(15.0 + 14.0 * u(rng)));
      s.scan.valid.push_back(i % 5 ? 1 : 0);
    }
    s.scan.sensor_pose = Pose2D(0.2 * u(rng), 0.1 * u(rng),
                                k % 11 == 0 ? -M_PI : M_PI * u(rng));
    log.steps.push_back(s);
  }
  return log;
}

TEST(NativeRawlogWriter, WritesTheBytesMrptWrites) {
  std::vector<hmt::Log> logs = {read_carmen(edmonton_path()),
                                read_rawlog(malaga_path()), awkward_log()};
  for (const auto& p : shared_carmen_logs()) logs.push_back(read_carmen(p));
  const std::string dir = scratch_dir();
  for (const hmt::Log& log : logs) {
    for (RawlogFormat f : kFormats) {
      SCOPED_TRACE(log.source + (f == RawlogFormat::kObservationsOnly
                                     ? " observations only"
                                     : " actions and sensory frames"));
      write_rawlog(log, dir + "/native.rawlog", f);
      write_rawlog(log, dir + "/native.rawlog.gz", f);
      write_rawlog_with_mrpt(log, dir + "/mrpt.rawlog", f);
      const std::string mrpt = read_bytes(dir + "/mrpt.rawlog");
      EXPECT_TRUE(read_bytes(dir + "/native.rawlog") == mrpt);
      EXPECT_TRUE(gunzip_file(dir + "/native.rawlog.gz") == mrpt);
    }
  }
}

// A rawlog with a camera image among the laser scans: read by MRPT.
TEST(MrptPlugin, ReadsClassesTheNativeReaderDoesNot) {
  const std::string p = scratch_dir() + "/multi_sensor.rawlog";
  auto sf = mrpt::obs::CSensoryFrame::Create();
  sf->insert(mrpt::obs::CObservationImage::Create());
  sf->insert(make_scan(2.0));
  write_objects(p, {make_odometry(0.5, 0, 0, 0), make_scan(1.0),
                    make_odometry(1.5, 1, 0, 0.1), sf,
                    mrpt::obs::CObservationGPS::Create(), make_scan(3.0)});
  const size_t fallbacks = detail::mrpt_fallback_reads();
  const hmt::Log log = read_log(p);
  EXPECT_EQ(detail::mrpt_fallback_reads(), fallbacks + 1);
  ASSERT_EQ(log.steps.size(), 3u);
  EXPECT_NEAR(log.steps[1].odometry_increment.x, 1.0, 1e-12);
  expect_identical_logs(log, detail::read_rawlog_with_mrpt(p, false, "test"));
}

TEST(MrptPlugin, MissingPluginIsAnInputErrorNamingClassAndFile) {
  const std::string p = scratch_dir() + "/image.rawlog";
  write_objects(p, {make_odometry(0.5, 0, 0, 0), make_scan(1.0),
                    mrpt::obs::CObservationImage::Create(), make_scan(2.0)});
  ASSERT_EQ(setenv("HMT_IO_MRPT_PLUGIN", "/nonexistent/libhmt_io_mrpt.so", 1),
            0);
  expect_input_error([&] { read_rawlog(p); },
                     {p, "CObservationImage", "entry 2", "plugin",
                      "/nonexistent/libhmt_io_mrpt.so"});
  unsetenv("HMT_IO_MRPT_PLUGIN");
  EXPECT_EQ(read_rawlog(p).steps.size(), 2u);
}

TEST(MrptPlugin, LaserAndOdometryLogsNeverNeedIt) {
  const size_t fallbacks = detail::mrpt_fallback_reads();
  const std::string dir = scratch_dir();
  const hmt::Log carmen = read_carmen(edmonton_path());
  for (RawlogFormat f : kFormats) {
    write_rawlog(carmen, dir + "/edmonton.rawlog.gz", f);
    EXPECT_EQ(read_log(dir + "/edmonton.rawlog.gz").steps.size(), 340u);
  }
  EXPECT_EQ(read_log(malaga_path()).steps.size(), 225u);
  EXPECT_EQ(detail::mrpt_fallback_reads(), fallbacks);
}

// Damaged files are read without MRPT: a damaged class name must not send
// garbage to MRPT's unchecking deserializers.
class DamagedRawlog : public ::testing::Test {
 protected:
  void SetUp() override {
    setenv("HMT_IO_MRPT_PLUGIN", "/nonexistent/libhmt_io_mrpt.so", 1);
  }
  void TearDown() override { unsetenv("HMT_IO_MRPT_PLUGIN"); }

  // Reading `bytes` either works or fails with an InputError naming the
  // file; returns the message ("" if it worked).
  std::string read_damaged(const std::string& bytes) {
    write_bytes(path_, bytes);
    try {
      read_rawlog(path_);
      return "";
    } catch (const hmt::InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(path_), std::string::npos) << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
      return msg;
    }
  }

  std::string path_ = scratch_dir() + "/damaged.rawlog";
};

TEST_F(DamagedRawlog, EveryCutIsAnInputError) {
  const std::string bytes = gunzip_file(malaga_path());
  // The first entry (a sensory frame) is 2049 bytes: every cut inside it.
  for (size_t cut = 1; cut < 2049; ++cut) {
    const std::string msg = read_damaged(bytes.substr(0, cut));
    EXPECT_NE(msg.find("is truncated: entry 0"), std::string::npos)
        << "cut at " << cut << ": " << msg;
  }
  // Then cuts all over the file.
  for (size_t cut = 2050; cut < bytes.size(); cut += 4999)
    read_damaged(bytes.substr(0, cut));
}

TEST_F(DamagedRawlog, FlippedBytesNeverCrash) {
  const std::string bytes = gunzip_file(malaga_path()).substr(0, 60000);
  std::mt19937 rng(11);
  std::uniform_int_distribution<size_t> pos(0, bytes.size() - 1);
  std::uniform_int_distribution<int> bit(0, 7);
  size_t failures = 0;
  for (int trial = 0; trial < 1500; ++trial) {
    std::string damaged = bytes;
    for (int k = 0; k < 1 + trial % 3; ++k)
      damaged[pos(rng)] ^= static_cast<char>(1 << bit(rng));
    if (!read_damaged(damaged).empty()) ++failures;
  }
  // Most flips hit range readings, which stay readable.
  EXPECT_GT(failures, 50u);
}

// A count that promises more than the file holds costs no more memory than
// the file: the read runs into the end of the data.
TEST_F(DamagedRawlog, AbsurdCounts) {
  Bytes pose;
  pose.f64(0).f64(0).f64(0);
  for (int i = 0; i < 9; ++i) pose.f64(i % 4 == 0 ? 1 : 0);
  Bytes scan;
  scan.f32(3.14f).boolean(true).f32(80.0f).obj("CPose3D", 3, pose);
  scan.u32(0xffffffffu).f32(1.0f).f32(2.0f);
  const std::string msg = read_damaged(
      Bytes().obj("CObservation2DRangeScan", 7, scan).bytes());
  EXPECT_NE(msg.find("is truncated: entry 0"), std::string::npos) << msg;
  Bytes frame;
  frame.u32(0xffffffffu).null_obj().null_obj();
  EXPECT_NE(read_damaged(Bytes().obj("CSensoryFrame", 2, frame).bytes())
                .find("is truncated: entry 0"),
            std::string::npos);
}

TEST_F(DamagedRawlog, MalformedObjects) {
  const std::string good = gunzip_file(malaga_path()).substr(0, 2049);
  Bytes nested;  // frames inside frames, far deeper than any rawlog
  for (int i = 0; i < 200; ++i) nested.u8(0x80 | 13).raw("CSensoryFrame", 13).u8(2).u32(1);
  std::string bad_end = good;
  bad_end.back() = 0x11;  // the frame's end flag
  std::string bad_version = good;
  bad_version[14] = 9;  // CSensoryFrame version 9
  for (const std::string& entry1 :
       {nested.bytes(), bad_end, bad_version, std::string("\x85" "C@#!x", 6),
        std::string("\x01\x02\x00\x00", 4)}) {
    const std::string msg = read_damaged(good + entry1 + good);
    EXPECT_NE(msg.find("is corrupt: entry 1 cannot be read"),
              std::string::npos)
        << msg;
  }
}

}  // namespace
}  // namespace hmt::io

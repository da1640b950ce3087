// Every kind of bad input must end in a clear one-line hmt::InputError, never
// a crash, a hang or a silently short log.
#include <gtest/gtest.h>

#include <mrpt/obs/CObservationGPS.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "hmt/io/carmen.h"
#include "hmt/io/log_reader.h"
#include "hmt/io/rawlog.h"
#include "hmt/io/tum.h"
#include "io_test_util.h"
#include "mrpt_test_util.h"

namespace hmt::io {
namespace {

using namespace testing_util;

std::string random_bytes(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::string s(n, '\0');
  for (auto& c : s) c = static_cast<char>(rng() & 0xff);
  return s;
}


TEST(InputRejection, MissingFile) {
  const std::string p = scratch_dir() + "/nothing.log";
  expect_input_error([&] { read_log(p); }, {p, "does not exist"});
  expect_input_error([&] { read_rawlog(p); }, {p, "does not exist"});
  expect_input_error([&] { read_carmen(p); }, {p, "does not exist"});
  expect_input_error([&] { read_tum(p); }, {p, "does not exist"});
}

TEST(InputRejection, Directory) {
  const std::string d = scratch_dir();
  expect_input_error([&] { read_log(d); }, {d, "not a regular file"});
  expect_input_error([&] { read_rawlog(d); }, {d, "not a regular file"});
  expect_input_error([&] { read_carmen(d); }, {d, "not a regular file"});
}

TEST(InputRejection, EmptyFile) {
  const std::string p = scratch_dir() + "/empty.log";
  write_bytes(p, "");
  expect_input_error([&] { read_log(p); }, {p, "is empty"});
  expect_input_error([&] { read_rawlog(p); }, {p, "is empty"});
  expect_input_error([&] { read_carmen(p); }, {p, "is empty"});
}

TEST(InputRejection, EmptyGzipFile) {
  const std::string p = scratch_dir() + "/empty.log.gz";
  write_bytes(p, gzip_bytes(""));
  expect_input_error([&] { read_log(p); }, {p, "no 2D laser scans"});
  expect_input_error([&] { read_carmen(p); }, {p, "is empty"});
}

TEST(InputRejection, RandomBytes) {
  const std::string dir = scratch_dir();
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const std::string p = dir + "/random" + std::to_string(seed) + ".bin";
    write_bytes(p, random_bytes(4096 + seed * 100, seed));
    expect_input_error([&] { read_log(p); },
                       {p, "neither a CARMEN log nor an MRPT rawlog"});
    expect_input_error([&] { read_rawlog(p); }, {p, "not an MRPT rawlog"});
    expect_input_error([&] { read_carmen(p); }, {p, "line 1"});
  }
}

TEST(InputRejection, RandomBytesGzipped) {
  const std::string p = scratch_dir() + "/random.bin.gz";
  write_bytes(p, gzip_bytes(random_bytes(10000, 7)));
  expect_input_error([&] { read_log(p); },
                     {p, "neither a CARMEN log nor an MRPT rawlog"});
}

TEST(InputRejection, CarmenStartFollowedByGarbage) {
  const std::string p = scratch_dir() + "/garbage.log";
  write_bytes(p, flaser(3, "1.5", 0, 1) + random_bytes(500, 3));
  expect_input_error([&] { read_log(p); }, {p, "line 2", "CARMEN message"});
}

TEST(InputRejection, TruncatedGzipRawlog) {
  const std::string gz = read_bytes(malaga_path());  // already gzip
  const std::string p = scratch_dir() + "/cut.rawlog.gz";
  write_bytes(p, gz.substr(0, gz.size() / 2));
  expect_input_error([&] { read_log(p); }, {p, "damaged gzip", "entry"});
  expect_input_error([&] { read_rawlog(p); }, {p, "damaged gzip", "entry"});
  // Only the 8-byte trailer (CRC and length) missing: all objects read.
  write_bytes(p, gz.substr(0, gz.size() - 8));
  expect_input_error([&] { read_rawlog(p); }, {p, "damaged gzip"});
  // Our own compression of the plain bytes, cut.
  const std::string regz = gzip_bytes(gunzip_file(malaga_path()));
  write_bytes(p, regz.substr(0, regz.size() / 3));
  expect_input_error([&] { read_rawlog(p); }, {p, "damaged gzip"});
}

TEST(InputRejection, CorruptGzipRawlog) {
  std::string gz = read_bytes(malaga_path());
  for (size_t i = gz.size() / 2; i < gz.size() / 2 + 64; ++i) gz[i] ^= 0x5a;
  const std::string p = scratch_dir() + "/corrupt.rawlog.gz";
  write_bytes(p, gz);
  expect_input_error([&] { read_rawlog(p); }, {p, "entry"});
}

TEST(InputRejection, TruncatedPlainRawlog) {
  const std::string bytes = gunzip_file(malaga_path());
  ASSERT_GT(bytes.size(), 400000u);
  const std::string p = scratch_dir() + "/cut.rawlog";
  for (size_t cut : {bytes.size() / 2, bytes.size() - 1, size_t(10)}) {
    write_bytes(p, bytes.substr(0, cut));
    expect_input_error([&] { read_log(p); }, {p, "is truncated: entry"});
    expect_input_error([&] { read_rawlog(p); }, {p, "is truncated: entry"});
  }
}

TEST(InputRejection, RawlogOfWrongObjectType) {
  const std::string p = scratch_dir() + "/pose.rawlog";
  write_objects(p, {std::make_shared<mrpt::poses::CPose2D>(1, 2, 3)});
  expect_input_error([&] { read_log(p); },
                     {p, "entry 0", "CPose2D", "not a rawlog entry"});
}

TEST(InputRejection, RawlogWithoutScans) {
  const std::string p = scratch_dir() + "/gps.rawlog";
  auto gps = mrpt::obs::CObservationGPS::Create();
  write_objects(p, {gps, gps});
  expect_input_error([&] { read_rawlog(p); }, {p, "no 2D laser scans"});
}

TEST(InputRejection, RawlogScansWithoutOdometry) {
  const std::string p = scratch_dir() + "/noodo.rawlog";
  write_objects(p, {make_scan(1.0), make_scan(2.0), make_scan(3.0)});
  expect_input_error([&] { read_log(p); }, {p, "3 laser scans", "no odometry"});
}

TEST(InputRejection, RawlogNanRange) {
  const std::string p = scratch_dir() + "/nan.rawlog";
  auto bad = make_scan(2.0);
  bad->setScanRange(3, std::nanf(""));
  write_objects(p, {make_odometry(0.5, 0, 0, 0), make_scan(1.0), bad});
  expect_input_error([&] { read_rawlog(p); },
                     {p, "scan 1 (entry 2)", "beam 3", "nan"});
}

TEST(InputRejection, RawlogNanRangeInSensoryFrame) {
  const std::string p = scratch_dir() + "/nan_sf.rawlog";
  auto bad = make_scan(2.0);
  bad->setScanRange(0, std::nanf(""));
  bad->setScanRangeValidity(0, false);  // NaN is an error even if flagged
  auto sf = std::make_shared<mrpt::obs::CSensoryFrame>();
  sf->insert(bad);
  write_objects(p, {sf});
  expect_input_error([&] { read_rawlog(p); }, {p, "scan 0 (entry 0)", "nan"});
}

TEST(InputRejection, RawlogNegativeRange) {
  const std::string p = scratch_dir() + "/neg.rawlog";
  auto bad = make_scan(1.0);
  bad->setScanRange(4, -2.0f);
  write_objects(p, {make_odometry(0.5, 0, 0, 0), bad});
  expect_input_error([&] { read_rawlog(p); }, {p, "scan 0", "beam 4", "-2"});
}

TEST(InputRejection, RawlogZeroBeamScan) {
  const std::string p = scratch_dir() + "/empty_scan.rawlog";
  auto bad = make_scan(2.0);
  bad->resizeScan(0);
  write_objects(p, {make_odometry(0.5, 0, 0, 0), make_scan(1.0), bad});
  expect_input_error([&] { read_rawlog(p); }, {p, "scan 1", "no beams"});
}

TEST(InputRejection, CarmenTooFewRanges) {
  const std::string p = scratch_dir() + "/short.log";
  std::string line = flaser(180, "2.5", 0, 1);
  // Drop ten readings: n still says 180.
  std::string cut = "FLASER 180";
  for (int i = 0; i < 170; ++i) cut += " 2.5";
  cut += " 0 0 0 0 0 0 1.0 host 1.0\n";
  write_bytes(p, "# a comment\n" + line + cut);
  expect_input_error([&] { read_log(p); },
                     {p, "line 3", "180 beams needs 191 fields, found 181"});
}

TEST(InputRejection, CarmenTooManyFields) {
  const std::string p = scratch_dir() + "/long.log";
  std::string line = flaser(4, "2.5", 0, 1);
  line.insert(line.size() - 1, " 7");
  write_bytes(p, line);
  expect_input_error([&] { read_carmen(p); }, {p, "line 1", "found 16"});
}

TEST(InputRejection, CarmenNanRange) {
  const std::string p = scratch_dir() + "/nan.log";
  write_bytes(p, flaser(4, "2.5", 0, 1) + "FLASER 4 1 2 nan 4 0 0 0 0 0 0 2 h 2\n");
  expect_input_error([&] { read_log(p); }, {p, "line 2", "range 2 is nan"});
}

TEST(InputRejection, CarmenInfiniteRange) {
  const std::string p = scratch_dir() + "/inf.log";
  write_bytes(p, "FLASER 4 1 inf 3 4 0 0 0 0 0 0 2 h 2\n");
  expect_input_error([&] { read_carmen(p); }, {p, "line 1", "range 1 is inf"});
}

TEST(InputRejection, CarmenNegativeRange) {
  const std::string p = scratch_dir() + "/neg.log";
  write_bytes(p, "FLASER 4 1 2 3 -4.5 0 0 0 0 0 0 2 h 2\n");
  expect_input_error([&] { read_carmen(p); }, {p, "line 1", "range 3 is -4.5"});
}

TEST(InputRejection, CarmenNonNumericField) {
  const std::string p = scratch_dir() + "/text.log";
  write_bytes(p, "FLASER 4 1 2 3 4 0 0 0 zero 0 0 2 h 2\n");
  expect_input_error([&] { read_carmen(p); },
                     {p, "line 1", "odom_x", "'zero', not a number"});
  write_bytes(p, "FLASER 4 1 2 x3 4 0 0 0 0 0 0 2 h 2\n");
  expect_input_error([&] { read_carmen(p); }, {p, "range 2", "'x3'"});
  write_bytes(p, "FLASER four 1 2 3 4 0 0 0 0 0 0 2 h 2\n");
  expect_input_error([&] { read_carmen(p); }, {p, "beam count", "'four'"});
}

TEST(InputRejection, CarmenZeroBeams) {
  const std::string p = scratch_dir() + "/zero.log";
  write_bytes(p, "FLASER 0 0 0 0 0 0 0 1.0 host 1.0\n");
  expect_input_error([&] { read_log(p); }, {p, "line 1", "0 beams"});
  write_bytes(p, "FLASER -3 0 0 0 0 0 0 1.0 host 1.0\n");
  expect_input_error([&] { read_log(p); }, {p, "line 1", "-3 beams"});
}

TEST(InputRejection, CarmenWithoutScans) {
  const std::string p = scratch_dir() + "/noscans.log";
  write_bytes(p, "# only parameters\nPARAM robot_frontlaser_offset 0.1\n"
                 "ODOM 0 0 0 0 0 0 1 h 1\n");
  expect_input_error([&] { read_log(p); }, {p, "no laser scans"});
}

TEST(InputRejection, CarmenBadParam) {
  const std::string p = scratch_dir() + "/param.log";
  write_bytes(p, "PARAM robot_frontlaser_offset forward\n" +
                     flaser(4, "1", 0, 1));
  expect_input_error([&] { read_carmen(p); },
                     {p, "line 1", "robot_frontlaser_offset", "'forward'"});
}

TEST(InputRejection, TruncatedGzipCarmen) {
  const std::string gz = read_bytes(edmonton_path());
  const std::string p = scratch_dir() + "/cut.log.gz";
  write_bytes(p, gz.substr(0, gz.size() / 2));
  // The cut usually falls mid-line, which would also be a field-count
  // error; the damaged compression is what must be reported.
  expect_input_error([&] { read_log(p); }, {p, "damaged gzip"});
}

}  // namespace
}  // namespace hmt::io

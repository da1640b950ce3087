// The MRPT plugin's stream (src/mrpt_fallback.h): a rawlog holding classes
// only MRPT reads is read entry by entry as the steps are taken, and gives
// the steps the native reader gives for the same file without those
// objects; damage and unusable logs fail where the reader meets them, after
// the good steps, with the messages the whole-file read gave.
#include <gtest/gtest.h>

#include <mrpt/io/CMemoryStream.h>
#include <mrpt/obs/CObservationGPS.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/poses/CPose2D.h>

#include <cmath>
#include <cstdlib>

#include "archive_bytes.h"
#include "hmt/io/carmen.h"
#include "hmt/io/log_reader.h"
#include "hmt/io/log_stream.h"
#include "hmt/io/rawlog.h"
#include "io_test_util.h"
#include "mrpt_fallback.h"
#include "mrpt_test_util.h"

namespace hmt::io {
namespace {

using namespace testing_util;
using mrpt::serialization::CSerializable;
using Objects = std::vector<CSerializable::Ptr>;

bool only_mrpt_reads(const CSerializable::Ptr& o) {
  return std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(o) ||
         std::dynamic_pointer_cast<mrpt::obs::CObservationGPS>(o);
}

// `objects` without those only MRPT reads (a frame keeps its other
// observations): what the native reader reads alone.
Objects without_mrpt_only(const Objects& objects) {
  Objects out;
  for (const auto& o : objects) {
    if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(o)) {
      auto kept = mrpt::obs::CSensoryFrame::Create();
      for (const auto& obs : *sf)
        if (!only_mrpt_reads(obs)) kept->insert(obs);
      out.push_back(kept);
    } else if (!only_mrpt_reads(o)) {
      out.push_back(o);
    }
  }
  return out;
}

// The steps `stream` hands out one by one, up to its end or its error
// (whose message goes to `error`).
hmt::Log steps_of(LogStream& stream, std::string* error = nullptr) {
  hmt::Log log;
  log.source = stream.source();
  LogStep step;
  try {
    while (stream.next(step)) {
      log.steps.push_back(step);
      EXPECT_GE(stream.fraction_read(), 0.0);
      EXPECT_LE(stream.fraction_read(), 1.0);
    }
    EXPECT_EQ(stream.fraction_read(), 1.0);
    EXPECT_FALSE(stream.next(step));  // stays at the end
    if (error) ADD_FAILURE() << "no InputError for " << log.source;
  } catch (const InputError& e) {
    if (!error) throw;
    *error = e.what();
  }
  return log;
}

// The files the tests of the MRPT plugin read (rawlog_native_test.cc,
// rawlog_test.cc, log_stream_test.cc), by name.
std::vector<std::pair<std::string, Objects>> plugin_test_inputs() {
  using mrpt::obs::CObservationGPS;
  using mrpt::obs::CObservationImage;
  return {
      {"multi_sensor",
       {make_odometry(0.5, 0, 0, 0), make_scan(1.0), make_odometry(1.5, 1, 0, 0.1),
        make_frame({CObservationImage::Create(), make_scan(2.0)}), CObservationGPS::Create(),
        make_scan(3.0)}},
      {"image",
       {make_odometry(0.5, 0, 0, 0), make_scan(1.0), CObservationImage::Create(),
        make_scan(2.0)}},
      {"observations_only",
       {make_scan(0.9), make_odometry(1.0, 10, 5, M_PI / 2), make_scan(1.1),
        make_odometry(1.2, 10, 6, M_PI / 2), make_odometry(1.3, 10, 7, M_PI),
        CObservationImage::Create(), make_scan(1.4), make_scan(1.5)}},
      {"actions_and_frames",
       {make_frame({make_scan(1.0)}), make_action(1.0, 0, 0), make_action(1.0, 0, M_PI / 2),
        make_frame({make_scan(2.0), make_scan(2.0)}),
        make_action(0.5, 0.1, 0.2, /*scan_matching=*/true),
        make_frame({CObservationImage::Create(), make_scan(3.0)})}},
      {"mid_file",
       {make_odometry(1.0, 0, 0, 0), make_scan(1.0), make_odometry(2.0, 1, 0, 0), make_scan(2.0),
        make_odometry(3.0, 2, 0, 0), make_scan(3.0), CObservationImage::Create(),
        make_odometry(4.0, 3, 0, 0), make_scan(4.0)}},
  };
}

TEST(MrptStream, YieldsWhatTheNativeReaderReadsWithoutTheMrptOnlyObjects) {
  const std::string dir = scratch_dir();
  for (const auto& [name, objects] : plugin_test_inputs()) {
    SCOPED_TRACE(name);
    const std::string p = dir + "/" + name + ".rawlog";
    write_objects(p, without_mrpt_only(objects));
    const size_t fallbacks = detail::mrpt_fallback_reads();
    const hmt::Log native = read_rawlog(p);
    ASSERT_EQ(detail::mrpt_fallback_reads(), fallbacks) << "read through MRPT";
    ASSERT_GE(native.steps.size(), 2u);

    write_objects(p, objects);
    // Through open_log(): the native reader meets the class and hands over.
    const hmt::Log through_log = steps_of(*open_log(p));
    EXPECT_EQ(detail::mrpt_fallback_reads(), fallbacks + 1);
    expect_identical_logs(through_log, native);
    // The plugin's stream alone, and drained.
    const auto mrpt = detail::open_rawlog_with_mrpt(p, false, "the test");
    expect_identical_logs(steps_of(*mrpt), native);
    expect_identical_logs(detail::read_rawlog_with_mrpt(p, false, "the test"), native);
  }
}

// The bytes MRPT writes for `object`.
std::string bytes_of(const CSerializable& object) {
  mrpt::io::CMemoryStream bytes;
  auto ar = mrpt::serialization::archiveFrom(bytes);
  ar << object;
  return std::string(static_cast<const char*>(bytes.getRawBufferData()),
                     bytes.getTotalBytesCount());
}

// The Edmonton log as MRPT objects (observations only), with a camera image
// as entry 2; and where each entry ends in the file.
struct LongInput {
  Objects objects;
  std::vector<size_t> entry_end;  // byte offset past each entry
  std::vector<size_t> scans_before;  // scans in the entries before each
};

LongInput long_input() {
  LongInput in;
  const hmt::Log edmonton = read_carmen(edmonton_path());
  Pose2D odometry;
  for (size_t k = 0; k < edmonton.steps.size(); ++k) {
    const LogStep& step = edmonton.steps[k];
    if (k > 0) odometry = odometry + step.odometry_increment;
    auto odo = mrpt::obs::CObservationOdometry::Create();
    odo->odometry = mrpt::poses::CPose2D(odometry.x, odometry.y, odometry.theta);
    odo->timestamp = mrpt::Clock::fromDouble(step.timestamp);
    in.objects.push_back(odo);
    in.objects.push_back(mrpt_scan(step.scan, step.timestamp));
    if (k == 0) in.objects.push_back(mrpt::obs::CObservationImage::Create());
  }
  size_t offset = 0, scans = 0;
  for (const auto& o : in.objects) {
    offset += bytes_of(*o).size();
    in.entry_end.push_back(offset);
    in.scans_before.push_back(scans);
    if (std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(o)) ++scans;
  }
  return in;
}

// Writes `in` to `path`, its entry `entry` replaced by `bytes`.
void write_with_entry(const std::string& path, const LongInput& in, size_t entry,
                      const std::string& bytes) {
  write_objects(path, in.objects);
  const std::string whole = read_bytes(path);
  const size_t begin = entry == 0 ? 0 : in.entry_end[entry - 1];
  write_bytes(path, whole.substr(0, begin) + bytes + whole.substr(in.entry_end[entry]));
}

class MrptStreamDamage : public ::testing::Test {
 protected:
  void SetUp() override {
    whole_ = steps_of(*open_log(good_));
    ASSERT_EQ(whole_.steps.size(), 340u);
  }

  // Streams `path`, expecting `message` (naming `path`) after exactly the
  // first `good` steps of the undamaged file.
  void expect_fails_after(const std::string& path, size_t good, const std::string& message) {
    std::string error;
    const hmt::Log got = steps_of(*open_log(path), &error);
    EXPECT_EQ(error, message);
    ASSERT_EQ(got.steps.size(), good);
    hmt::Log head = whole_;
    head.source = path;
    head.steps.resize(good);
    expect_identical_logs(got, head);
  }

  std::string dir_ = scratch_dir();
  LongInput in_ = long_input();
  std::string good_ = [this] {
    const std::string p = dir_ + "/good.rawlog";
    write_objects(p, in_.objects);
    return p;
  }();
  hmt::Log whole_;
  // An entry two thirds in, a scan's (even: entry 2 is the image).
  size_t entry_ = in_.objects.size() * 2 / 3 / 2 * 2;
};

TEST_F(MrptStreamDamage, ACutFileFailsWhereTheCutIs) {
  ASSERT_TRUE(std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(in_.objects[entry_]));
  const std::string p = dir_ + "/cut.rawlog";
  const std::string bytes = read_bytes(good_);
  write_bytes(p, bytes.substr(0, in_.entry_end[entry_] - 100));
  expect_fails_after(p, in_.scans_before[entry_],
                     "rawlog '" + p + "' is truncated: entry " + std::to_string(entry_) +
                         " cannot be read");
  // The same cut in a gzip file: the stream ends where zlib finds it.
  const std::string gz = dir_ + "/cut.rawlog.gz";
  write_bytes(gz, gzip_bytes(bytes).substr(0, gzip_bytes(bytes).size() * 2 / 3));
  std::string error;
  const hmt::Log got = steps_of(*open_log(gz), &error);
  EXPECT_NE(error.find("rawlog '" + gz + "' is a damaged gzip file (zlib: "), std::string::npos)
      << error;
  EXPECT_GT(got.steps.size(), 100u);
  EXPECT_LT(got.steps.size(), 340u);
}

TEST_F(MrptStreamDamage, ACorruptEntryFailsWhereItIs) {
  const std::string p = dir_ + "/corrupt.rawlog";
  write_with_entry(p, in_, entry_, std::string("\x85" "C@#!x", 6));
  expect_fails_after(p, in_.scans_before[entry_],
                     "rawlog '" + p + "' is corrupt: entry " + std::to_string(entry_) +
                         " cannot be read");
}

TEST_F(MrptStreamDamage, WrongAndEmptyEntriesFailWhereTheyAre) {
  const std::string p = dir_ + "/wrong.rawlog";
  write_with_entry(p, in_, entry_, bytes_of(mrpt::poses::CPose2D(1, 2, 3)));
  const std::string at = "rawlog '" + p + "' entry " + std::to_string(entry_);
  expect_fails_after(p, in_.scans_before[entry_],
                     at + " is a mrpt::poses::CPose2D, not a rawlog entry (CSensoryFrame, "
                          "CActionCollection or CObservation)");
  write_with_entry(p, in_, entry_, Bytes().null_obj().bytes());
  expect_fails_after(p, in_.scans_before[entry_], at + " is an empty object");
}

// What can only be known at the end is reported there, as by the native
// reader, after the steps (none: the scans wait for the odometry source).
TEST(MrptStream, NoScansOrNoOdometryFailAtTheEnd) {
  const std::string dir = scratch_dir();
  const std::string p = dir + "/no_scans.rawlog";
  write_objects(p, {make_odometry(1.0, 0, 0, 0), mrpt::obs::CObservationImage::Create(),
                    make_odometry(2.0, 1, 0, 0)});
  std::string error;
  EXPECT_TRUE(steps_of(*open_log(p), &error).steps.empty());
  EXPECT_EQ(error, "rawlog '" + p + "' holds no 2D laser scans (3 entries read)");
  const std::string q = dir + "/no_odometry.rawlog";
  write_objects(q, {make_scan(1.0), mrpt::obs::CObservationImage::Create(), make_scan(2.0)});
  EXPECT_TRUE(steps_of(*open_log(q), &error).steps.empty());
  EXPECT_EQ(error, "rawlog '" + q +
                       "' holds 2 laser scans but no odometry (neither CActionRobotMovement2D "
                       "nor CObservationOdometry)");
}

// The stream reads the file as the steps are taken, not whole up front.
TEST(MrptStream, ReadsTheFileAsTheStepsAreTaken) {
  const std::string p = scratch_dir() + "/long.rawlog";
  write_objects(p, long_input().objects);
  const auto stream = detail::open_rawlog_with_mrpt(p, false, "the test");
  EXPECT_EQ(stream->fraction_read(), 0.0);
  LogStep step;
  ASSERT_TRUE(stream->next(step));
  EXPECT_GT(stream->fraction_read(), 0.0);
  EXPECT_LT(stream->fraction_read(), 0.5);
  EXPECT_FALSE(stream->total_steps());
  size_t steps = 1;
  while (stream->next(step)) ++steps;
  EXPECT_EQ(steps, 340u);
  EXPECT_EQ(stream->fraction_read(), 1.0);
}

// A plugin of the whole-file reader (before the stream) is not used.
TEST(MrptStream, AnOutOfDatePluginIsRefused) {
  const std::string p = scratch_dir() + "/image.rawlog";
  write_objects(p, {make_odometry(0.5, 0, 0, 0), make_scan(1.0),
                    mrpt::obs::CObservationImage::Create(), make_scan(2.0)});
  ASSERT_EQ(setenv("HMT_IO_MRPT_PLUGIN", HMT_IO_V1_MRPT_PLUGIN, 1), 0);
  expect_input_error([&] { read_log(p); },
                     {p, "CObservationImage", "entry 2", "cannot be loaded", HMT_IO_V1_MRPT_PLUGIN,
                      "no hmt_io_mrpt_rawlog_plugin_v2 (another build?)"});
  unsetenv("HMT_IO_MRPT_PLUGIN");
  EXPECT_EQ(read_log(p).steps.size(), 2u);
}

}  // namespace
}  // namespace hmt::io

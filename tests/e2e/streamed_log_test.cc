// `hmt-slam run` reads its log as it goes: a rawlog (read natively or through
// the MRPT plugin), a CARMEN log or a ROS bag whose scans are several times
// the memory bound runs within that bound (the whole log read up front would
// not fit). The log is a robot standing in a round room with a dense
// scanner: large in memory, quick to run.
#include <gtest/gtest.h>

#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/LaserScan.h>
#include <sys/resource.h>
#include <zlib.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "hmt/io/log_stream.h"
#include "hmt/io/rawlog.h"
#include "run_app.h"

namespace hmt::e2e {
namespace {

constexpr size_t kScans = 6000;
constexpr size_t kBeams = 10000;
// Peak resident memory allowed (MB): the run itself needs ~15 MB; the
// decoded log is kScans * kBeams * 5 bytes = 286 MB (the whole-log reader
// peaked at 156 MB with half as many scans).
constexpr double kBoundMb = 60.0;

LogStep standing_step(size_t k) {
  LogStep s;
  s.timestamp = 0.1 * static_cast<double>(k);
  s.has_odometry = k > 0;
  s.scan.timestamp = s.timestamp;
  s.scan.angle_min = static_cast<float>(-M_PI / 2);
  s.scan.angle_increment = static_cast<float>(M_PI / (kBeams - 1));
  s.scan.max_range = 30.0f;
  s.scan.ranges.assign(kBeams, 4.0f);
  s.scan.valid.assign(kBeams, 1);
  return s;
}

hmt::Log standing_robot() {
  hmt::Log log;
  log.source = "standing robot";
  for (size_t k = 0; k < kScans; ++k) log.steps.push_back(standing_step(k));
  return log;
}

// Steps [first, last) of the standing robot, made as they are taken, for
// the rawlog writer.
class StandingSteps : public hmt::io::LogStream {
 public:
  StandingSteps(size_t first, size_t last) : LogStream("standing robot"), k_(first), last_(last) {}
  bool next(LogStep& out) override {
    if (k_ == last_) return false;
    out = standing_step(k_++);
    return true;
  }
  double fraction_read() const override { return 0.0; }

 private:
  size_t k_, last_;
};

// A run light enough for thousands of dense scans.
const std::string kLight = " --set metric_slam.particles=4 --set scan_matcher.beam_skip=99";

// Runs `log` (in `dir`) and checks every scan was processed within the bound.
void expect_bounded_run(const std::string& dir, const std::string& log, double log_mb,
                        double bound_mb = kBoundMb) {
  ASSERT_GT(log_mb, 4 * bound_mb);
  const AppResult r =
      run_app("run --quiet --input '" + log + "' --out '" + dir + "/out'" + kLight, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto summary = nlohmann::json::parse(slurp(dir + "/out/summary.json"));
  EXPECT_EQ(summary["scans"].get<size_t>(), kScans);
  const double peak_mb = summary["peak_rss_mb"].get<double>();
  EXPECT_LT(peak_mb, bound_mb) << "log " << log_mb << " MB";
}

// `convert` (to `format`) streams the log too; then no child of this test so
// far (the runs and the conversion) held more than the bound.
void expect_bounded_convert(const std::string& dir, const std::string& log,
                            const std::string& format = "obs", double bound_mb = kBoundMb) {
  const AppResult c = run_app("convert --input '" + log + "' --output '" + dir +
                                  "/standing.rawlog.gz' --format " + format,
                              dir);
  ASSERT_EQ(c.exit_code, 0) << c.err;
  EXPECT_NE(c.out.find("wrote " + std::to_string(kScans) + " scans"), std::string::npos) << c.out;
  struct rusage children {};
  ASSERT_EQ(getrusage(RUSAGE_CHILDREN, &children), 0);
  EXPECT_LT(static_cast<double>(children.ru_maxrss) / 1024.0, bound_mb);
}

TEST(StreamedLog, LongRawlogRunsInBoundedMemory) {
  if (kSanitizerBuild)
    GTEST_SKIP() << "sanitizer runtimes add their own memory: the bound is for the real build";
  const std::string dir = temp_dir("streamed_log");
  const std::string rawlog = dir + "/standing.rawlog.gz";
  hmt::io::write_rawlog(standing_robot(), rawlog, hmt::io::RawlogFormat::kObservationsOnly);
  expect_bounded_run(dir, rawlog, kScans * kBeams * 5.0 / (1024.0 * 1024.0));
}

// A CARMEN log is read twice, a line at a time (its no-return threshold and
// dead beams are decided over every scan first). Held whole it took the
// text (240 MB here) and the parsed scans (another 240 MB).
TEST(StreamedLog, LongCarmenLogRunsInBoundedMemory) {
  if (kSanitizerBuild)
    GTEST_SKIP() << "sanitizer runtimes add their own memory: the bound is for the real build";
  const std::string dir = temp_dir("streamed_carmen");
  const std::string path = dir + "/standing.log";
  {
    std::ofstream out(path);
    std::string ranges;
    for (size_t i = 0; i < kBeams; ++i) ranges += i == 0 ? "4.00" : " 4.0";
    for (size_t k = 0; k < kScans; ++k)
      out << "FLASER " << kBeams << ' ' << ranges << " 0 0 0 0 0 0 " << 0.1 * double(k)
          << " host " << 0.1 * double(k) << '\n';
    ASSERT_TRUE(out.good());
  }
  // What the whole-file reader held at once: the text and the parsed ranges.
  const double held_mb =
      (static_cast<double>(std::filesystem::file_size(path)) + kScans * kBeams * 4.0) /
      (1024.0 * 1024.0);
  expect_bounded_run(dir, path, held_mb);

  // `metric` streams too.
  const AppResult m =
      run_app("metric --quiet --input '" + path + "' --out '" + dir + "/metric'" + kLight, dir);
  ASSERT_EQ(m.exit_code, 0) << m.err;
  EXPECT_EQ(nlohmann::json::parse(slurp(dir + "/metric/summary.json"))["scans"].get<size_t>(),
            kScans);
  expect_bounded_convert(dir, path);
  std::filesystem::remove(path);
}

// A ROS bag is read twice through the plugin: the first pass keeps the
// odometry and transforms and, of the scans, all but their readings; the
// second decodes one scan at a time. Held whole it took the decoded
// readings (4 bytes a beam) and the steps made of them (5 more).
TEST(StreamedLog, LongRosBagRunsInBoundedMemory) {
  if (kSanitizerBuild)
    GTEST_SKIP() << "sanitizer runtimes add their own memory: the bound is for the real build";
  const std::string dir = temp_dir("streamed_bag");
  const std::string path = dir + "/standing.bag";
  {
    // Message by message: holding the log here to give it to the project's
    // bag writer would raise this process's peak memory, which the children
    // it starts report as theirs (they begin as its clones).
    rosbag::Bag bag;
    bag.open(path, rosbag::bagmode::Write);
    nav_msgs::Odometry odom;
    odom.header.frame_id = "odom";
    odom.child_frame_id = "base_link";
    odom.pose.pose.orientation.w = 1.0;
    sensor_msgs::LaserScan scan;
    scan.header.frame_id = "base_link";  // the laser at the robot's origin
    scan.angle_min = static_cast<float>(-M_PI / 2);
    scan.angle_increment = static_cast<float>(M_PI / (kBeams - 1));
    scan.angle_max = static_cast<float>(M_PI / 2);
    scan.range_max = 30.0f;
    scan.ranges.assign(kBeams, 4.0f);
    for (size_t k = 0; k < kScans; ++k) {
      const ros::Time stamp(1.0 + 0.1 * static_cast<double>(k));
      odom.header.stamp = scan.header.stamp = stamp;
      bag.write("/odom", stamp, odom);
      bag.write("/scan", stamp, scan);
    }
    bag.close();
  }
  ASSERT_GT(std::filesystem::file_size(path), kScans * kBeams * 4);
  expect_bounded_run(dir, path, kScans * kBeams * 9.0 / (1024.0 * 1024.0));
  expect_bounded_convert(dir, path);
  std::filesystem::remove(path);
}

// A rawlog that also holds an object only MRPT decodes is read through the
// MRPT plugin, entry by entry too. MRPT's libraries, mapped into the process
// for the plugin, take ~60 MB by themselves (the run below peaks at ~70 MB);
// the file read whole by the plugin, as it was, took 355 MB.
constexpr double kMrptBoundMb = 100.0;

// What MRPT 2.5.8 writes for mrpt::obs::CObservationImage::Create() with its
// timestamp zeroed, a class the native reader does not know: the camera's
// pose (a CPose3D at the origin), its calibration (a TCamera of 640 x 480
// named camera1, zeros elsewhere), an empty CImage, no time, no label.
std::string camera_image_bytes() {
  const auto header = [](const std::string& cls, int version) {
    return static_cast<char>(0x80 | cls.size()) + cls + static_cast<char>(version);
  };
  const auto zeros = [](size_t n) { return std::string(n, '\0'); };
  const std::string one("\0\0\0\0\0\0\xf0\x3f", 8);  // 1.0
  const std::string end = "\x88";
  return header("mrpt::obs::CObservationImage", 4) +
         header("mrpt::poses::CPose3D", 3) + zeros(24) + one + zeros(24) + one + zeros(24) +
         one + end +
         header("mrpt::img::TCamera", 6) + zeros(104) +
         std::string("\xe0\x01\0\0\x80\x02\0\0\x07\0\0\0camera1\0", 20) + end +
         header("mrpt::img::CImage", 9) + zeros(23) + end +
         zeros(12) + end;
}

TEST(StreamedLog, LongRawlogThroughTheMrptPluginRunsInBoundedMemory) {
  if (kSanitizerBuild)
    GTEST_SKIP() << "sanitizer runtimes add their own memory: the bound is for the real build";
  const std::string dir = temp_dir("streamed_mrpt");
  const std::string path = dir + "/standing_camera.rawlog.gz";
  const std::string rest = dir + "/rest.rawlog.gz";
  {
    // Step by step (see the bag test), as three gzip members, read as one
    // stream: half the scans, the camera image, the other half. The robot
    // stands at the origin, so the halves' odometry readings (each starting
    // there) are those of one log.
    StandingSteps first(0, kScans / 2), second(kScans / 2, kScans);
    hmt::io::write_rawlog(first, path, hmt::io::RawlogFormat::kObservationsOnly);
    hmt::io::write_rawlog(second, rest, hmt::io::RawlogFormat::kObservationsOnly);
    gzFile image = gzopen(path.c_str(), "ab");
    ASSERT_NE(image, nullptr);
    const std::string bytes = camera_image_bytes();
    ASSERT_EQ(gzwrite(image, bytes.data(), static_cast<unsigned>(bytes.size())),
              static_cast<int>(bytes.size()));
    ASSERT_EQ(gzclose(image), Z_OK);
    std::ofstream out(path, std::ios::binary | std::ios::app);
    out << std::ifstream(rest, std::ios::binary).rdbuf();
    ASSERT_TRUE(out.good());
  }
  std::filesystem::remove(rest);

  // The image sends the reader to the plugin: without it, no read.
  ASSERT_EQ(setenv("HMT_IO_MRPT_PLUGIN", "/nonexistent/libhmt_io_mrpt.so", 1), 0);
  const AppResult without = run_app(
      "convert --input '" + path + "' --output '" + dir + "/unread.rawlog.gz' --format obs", dir);
  unsetenv("HMT_IO_MRPT_PLUGIN");
  EXPECT_NE(without.exit_code, 0);
  EXPECT_NE(without.err.find("CObservationImage"), std::string::npos) << without.err;

  expect_bounded_run(dir, path, kScans * kBeams * 9.0 / (1024.0 * 1024.0), kMrptBoundMb);
  expect_bounded_convert(dir, path, "sf", kMrptBoundMb);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace hmt::e2e

// `hmt-slam run` reads its log as it goes: a rawlog, a CARMEN log or a ROS
// bag whose scans are several times the memory bound runs within that bound
// (the whole log read up front would not fit). The log is a robot standing
// in a round room with a dense scanner: large in memory, quick to run.
#include <gtest/gtest.h>

#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/LaserScan.h>
#include <sys/resource.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

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

hmt::Log standing_robot() {
  hmt::Log log;
  log.source = "standing robot";
  for (size_t k = 0; k < kScans; ++k) {
    LogStep s;
    s.timestamp = 0.1 * static_cast<double>(k);
    s.has_odometry = k > 0;
    s.scan.timestamp = s.timestamp;
    s.scan.angle_min = static_cast<float>(-M_PI / 2);
    s.scan.angle_increment = static_cast<float>(M_PI / (kBeams - 1));
    s.scan.max_range = 30.0f;
    s.scan.ranges.assign(kBeams, 4.0f);
    s.scan.valid.assign(kBeams, 1);
    log.steps.push_back(std::move(s));
  }
  return log;
}

// A run light enough for thousands of dense scans.
const std::string kLight = " --set metric_slam.particles=4 --set scan_matcher.beam_skip=99";

// Runs `log` (in `dir`) and checks every scan was processed within the bound.
void expect_bounded_run(const std::string& dir, const std::string& log, double log_mb) {
  ASSERT_GT(log_mb, 4 * kBoundMb);
  const AppResult r =
      run_app("run --quiet --input '" + log + "' --out '" + dir + "/out'" + kLight, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto summary = nlohmann::json::parse(slurp(dir + "/out/summary.json"));
  EXPECT_EQ(summary["scans"].get<size_t>(), kScans);
  const double peak_mb = summary["peak_rss_mb"].get<double>();
  EXPECT_LT(peak_mb, kBoundMb) << "log " << log_mb << " MB";
}

// `convert` streams the log too; then no child of this test so far (the
// runs and the conversion) held more than the bound.
void expect_bounded_convert(const std::string& dir, const std::string& log) {
  const AppResult c = run_app("convert --input '" + log + "' --output '" + dir +
                                  "/standing.rawlog.gz' --format obs",
                              dir);
  ASSERT_EQ(c.exit_code, 0) << c.err;
  EXPECT_NE(c.out.find("wrote " + std::to_string(kScans) + " scans"), std::string::npos) << c.out;
  struct rusage children {};
  ASSERT_EQ(getrusage(RUSAGE_CHILDREN, &children), 0);
  EXPECT_LT(static_cast<double>(children.ru_maxrss) / 1024.0, kBoundMb);
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

}  // namespace
}  // namespace hmt::e2e

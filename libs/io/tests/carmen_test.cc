// Reading CARMEN logs: the embedded Edmonton log, the other public logs when
// they are around, and small hand-written logs for the format's corners.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>

#include "hmt/io/carmen.h"
#include "hmt/io/log_reader.h"
#include "io_test_util.h"

namespace hmt::io {
namespace {

using namespace testing_util;

double odometry_path(const hmt::Log& log) {
  double path = 0.0;
  for (const auto& s : log.steps) path += s.odometry_increment.norm();
  return path;
}

TEST(CarmenConversion, Edmonton) {
  EXPECT_EQ(detect_log_format(edmonton_path()), LogFormat::kCarmen);
  const hmt::Log log = read_log(edmonton_path());
  ASSERT_EQ(log.steps.size(), 340u);
  EXPECT_FALSE(log.steps[0].has_odometry);
  size_t invalid = 0;
  for (size_t k = 0; k < log.steps.size(); ++k) {
    const LogStep& s = log.steps[k];
    EXPECT_EQ(s.has_odometry, k > 0);
    EXPECT_LT(s.odometry_increment.norm(), 3.0);
    ASSERT_EQ(s.scan.size(), 180u);
    ASSERT_EQ(s.scan.valid.size(), 180u);
    EXPECT_FLOAT_EQ(s.scan.angle_min, -M_PI / 2);
    EXPECT_FLOAT_EQ(s.scan.angle_increment, M_PI / 180);
    // No-returns are written as 51.09..51.16 m; the threshold is 0.3 m
    // below the log's largest reading.
    EXPECT_FLOAT_EQ(s.scan.max_range, 51.16f - 0.3f);
    EXPECT_EQ(s.scan.sensor_pose.x, 0.0);
    for (size_t i = 0; i < s.scan.size(); ++i) {
      EXPECT_EQ(s.scan.valid[i] == 0, s.scan.ranges[i] >= s.scan.max_range);
      invalid += s.scan.valid[i] == 0;
    }
  }
  EXPECT_EQ(invalid, 3367u);  // 51.09 (8) .. 51.16 (61) in the whole log
  EXPECT_DOUBLE_EQ(log.steps[0].timestamp, 18.0876);
  EXPECT_DOUBLE_EQ(log.steps[1].timestamp, 21.6373);
  // Odometry path: the README says 324 m.
  EXPECT_NEAR(odometry_path(log), 324.0, 0.2 * 324.0);
  // First line: "FLASER 180 12.06 12.11 12.91 51.16 ..."
  EXPECT_FLOAT_EQ(log.steps[0].scan.ranges[0], 12.06f);
  EXPECT_EQ(log.steps[0].scan.valid[3], 0);
}

struct PublicLog {
  const char* name;
  size_t scans, beams;
  double path;          // metres, from the datasets README
  float no_return_top;  // the log's largest reading
  double laser_offset;
};

class PublicLogConversion : public ::testing::TestWithParam<PublicLog> {};

TEST_P(PublicLogConversion, MatchTheReadme) {
  const PublicLog& d = GetParam();
  const std::string p = shared_carmen_path(d.name);
  if (!std::filesystem::exists(p)) GTEST_SKIP() << p << " not available";
  const hmt::Log log = read_log(p);
  ASSERT_EQ(log.steps.size(), d.scans);
  for (const auto& s : log.steps) {
    ASSERT_EQ(s.scan.size(), d.beams);
    EXPECT_FLOAT_EQ(s.scan.max_range, d.no_return_top - 0.3f);
    EXPECT_DOUBLE_EQ(s.scan.sensor_pose.x, d.laser_offset);
  }
  EXPECT_NEAR(odometry_path(log), d.path, 0.05 * d.path);
  const double res = d.beams >= 360 ? 0.5 : 1.0;
  EXPECT_FLOAT_EQ(log.steps[0].scan.angle_increment, res * M_PI / 180);
}

INSTANTIATE_TEST_SUITE_P(
    Readme, PublicLogConversion,
    ::testing::Values(PublicLog{"edmonton", 340, 180, 324, 51.16f, 0.0},
                      PublicLog{"aces", 440, 180, 323, 50.0f, 0.0},
                      PublicLog{"intel", 910, 180, 500, 81.83f, 0.0},
                      PublicLog{"csail", 406, 361, 380, 81.91f, 0.0},
                      PublicLog{"seattle", 241, 361, 190, 81.91f, 0.0},
                      PublicLog{"freiburg-101", 292, 360, 211, 81.91f, -0.04},
                      PublicLog{"fhw", 488, 180, 406, 51.1f, 0.0},
                      PublicLog{"acapulco", 861, 181, 812, 51.25f, 0.0},
                      PublicLog{"infinite-corridor", 1941, 180, 1920, 51.16f,
                                0.0}),
    [](const ::testing::TestParamInfo<PublicLog>& info) {
      std::string n = info.param.name;
      for (auto& c : n)
        if (c == '-') c = '_';
      return n;
    });

TEST(CarmenConversion, IntelReadsFast) {
  const std::string p = shared_carmen_path("intel");
  if (!std::filesystem::exists(p)) GTEST_SKIP() << p << " not available";
  const auto t0 = std::chrono::steady_clock::now();
  const hmt::Log log = read_log(p);
  const double s = std::chrono::duration<double>(
                       std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(log.steps.size(), 910u);
  EXPECT_LT(s, 1.0) << "reading intel took " << s << " s";
}

// Acapulco's 181st beam reads 50.00 in every scan: not a measurement.
TEST(CarmenConversion, AcapulcoConstantBeamIsInvalid) {
  const std::string p = shared_carmen_path("acapulco");
  if (!std::filesystem::exists(p)) GTEST_SKIP() << p << " not available";
  const hmt::Log log = read_carmen(p);
  size_t valid_last = 0;
  for (const auto& s : log.steps) valid_last += s.scan.valid[180];
  EXPECT_EQ(valid_last, 0u);
  // Its no-return codes (51.09..51.25) are all caught by the band.
  size_t valid_far = 0;
  for (const auto& s : log.steps)
    for (size_t i = 0; i < s.scan.size(); ++i)
      valid_far += s.scan.ranges[i] > 51.0f && s.scan.valid[i];
  EXPECT_EQ(valid_far, 0u);
}

std::string flaser_line(const std::vector<std::string>& ranges, double ox,
                        double oy, double oth, const std::string& t) {
  std::string line = "FLASER " + std::to_string(ranges.size());
  for (const auto& r : ranges) line += " " + r;
  char pose[128];
  std::snprintf(pose, sizeof(pose), " 9 9 9 %.6f %.6f %.6f ", ox, oy, oth);
  return line + pose + t + " nohost " + t + "\n";
}

TEST(CarmenConversion, SmallLogAndIgnoredLines) {
  const std::string p = scratch_dir() + "/small.log";
  write_bytes(p,
              "# CARMEN Logfile\r\n"
              "# file format is ...\n"
              "\n"
              "PARAM robot_front_laser_max 10 nohost 0\n"
              "PARAM robot_frontlaser_offset 0.25 nohost 0\n"
              "ODOM 1 2 3 0 0 0 0.5 nohost 0.5\n"
              "TRUEPOS 1 2 3 4 5 6 0.5 nohost 0.5\n" +
                  flaser_line({"1.5", "0", "60.5", "2"}, 1, 1, M_PI / 2, "1.25") +
                  "RAWLASER1 whatever 1 2 3\n" +
                  flaser_line({"1.5", "60.4", "+3", "2.25"}, 1, 3, M_PI, "0.75"));
  const hmt::Log log = read_log(p);
  ASSERT_EQ(log.steps.size(), 2u);
  const LogStep& a = log.steps[0];
  const LogStep& b = log.steps[1];
  EXPECT_DOUBLE_EQ(a.timestamp, 1.25);
  EXPECT_DOUBLE_EQ(b.timestamp, 0.75);  // kept, even going backwards
  EXPECT_DOUBLE_EQ(a.scan.sensor_pose.x, 0.25);
  // From (1,1,90deg) to (1,3,180deg): 2 m ahead, 90 deg left.
  // (the log holds the angles to 6 decimals)
  EXPECT_NEAR(b.odometry_increment.x, 2.0, 1e-5);
  EXPECT_NEAR(b.odometry_increment.y, 0.0, 1e-5);
  EXPECT_NEAR(b.odometry_increment.theta, M_PI / 2, 1e-6);
  // 4 beams: spread over 180 degrees.
  EXPECT_FLOAT_EQ(a.scan.angle_min, -M_PI / 2);
  EXPECT_FLOAT_EQ(a.scan.angle_increment, M_PI / 3);
  // 60.5 and 60.4 are within 0.3 m of the top: a recurring no-return code.
  EXPECT_FLOAT_EQ(a.scan.max_range, 60.5f - 0.3f);
  EXPECT_EQ(a.scan.valid, (std::vector<uint8_t>{1, 0, 0, 1}));
  EXPECT_EQ(b.scan.valid, (std::vector<uint8_t>{1, 0, 1, 1}));
  EXPECT_EQ(b.scan.ranges[2], 3.0f);
}

TEST(CarmenConversion, UniqueLargestReadingIsARealReturn) {
  const std::string p = scratch_dir() + "/nomax.log";
  write_bytes(p, flaser_line({"1", "2", "3"}, 0, 0, 0, "1") +
                     flaser_line({"1", "2", "7.5"}, 0, 0, 0, "2"));
  const hmt::Log log = read_carmen(p);
  ASSERT_EQ(log.steps.size(), 2u);
  EXPECT_EQ(log.steps[1].scan.valid, (std::vector<uint8_t>{1, 1, 1}));
  EXPECT_GT(log.steps[1].scan.max_range, 7.5f);
  EXPECT_LT(log.steps[1].scan.max_range, 7.6f);
}

TEST(CarmenConversion, BeamResolutionByCount) {
  const std::string p = scratch_dir() + "/res.log";
  for (auto [n, res] : std::vector<std::pair<int, double>>{
           {180, 1.0}, {181, 1.0}, {360, 0.5}, {361, 0.5}, {91, 2.0}}) {
    write_bytes(p, flaser_line(std::vector<std::string>(n, "1"), 0, 0, 0, "1"));
    const hmt::Log log = read_carmen(p);
    EXPECT_FLOAT_EQ(log.steps[0].scan.angle_increment, res * M_PI / 180)
        << n << " beams";
  }
}

TEST(CarmenConversion, BeamAnglesFromTheLogsParams) {
  // A FLASER line holds ranges only; where the count is not a SICK
  // scanner's, the log's PARAMs say what the laser was: a 270 degree laser of
  // 271 beams a degree apart, centred on the heading, by its resolution
  // (degrees) or by its field of view (degrees, or radians up to 2 pi).
  const std::string p = scratch_dir() + "/params.log";
  const std::string scan = flaser_line(std::vector<std::string>(271, "1"), 0, 0, 0, "1");
  for (const std::string param :
       {"PARAM laser_front_laser_resolution 1.0 nohost 0\n",
        "PARAM laser_front_laser_fov 270 nohost 0\n",
        "PARAM laser_front_laser_fov 4.71238898 nohost 0\n"}) {
    write_bytes(p, param + scan);
    const hmt::Log log = read_carmen(p);
    EXPECT_NEAR(log.steps[0].scan.angle_min, -135.0 * M_PI / 180, 1e-6) << param;
    EXPECT_NEAR(log.steps[0].scan.angle_increment, M_PI / 180, 1e-7) << param;
  }
  // PARAMs of a 180 degree span (the shared logs': 1 degree for 180 beams,
  // 0.5 for 360) keep the count's rule, first beam at -90 degrees.
  write_bytes(p, "PARAM laser_front_laser_resolution 1.0 nohost 0\n" +
                     flaser_line(std::vector<std::string>(180, "1"), 0, 0, 0, "1"));
  EXPECT_FLOAT_EQ(read_carmen(p).steps[0].scan.angle_min, static_cast<float>(-M_PI / 2));
  // A span no laser has, or a step that is not a number above 0: refused.
  write_bytes(p, "PARAM laser_front_laser_resolution 2.0 nohost 0\n" + scan);
  EXPECT_THROW(
      {
        try {
          read_carmen(p);
        } catch (const InputError& e) {
          EXPECT_NE(std::string(e.what()).find("more than a full turn"), std::string::npos)
              << e.what();
          throw;
        }
      },
      InputError);
  write_bytes(p, "PARAM laser_front_laser_resolution -1 nohost 0\n" + scan);
  EXPECT_THROW(read_carmen(p), InputError);
}

TEST(CarmenConversion, RobotLaserOnlyLog) {
  const std::string p = scratch_dir() + "/robotlaser.log";
  // type start fov res maxr acc rem n r.. m laser(x y th) robot(x y th)
  // tv rv fsd ssd turn ts host lts
  write_bytes(p,
              "ROBOTLASER1 0 -1.5 3.0 1.0 20 0.01 0 4 1 2 3 4 0 "
              "1.2 2.0 0.5 1.0 2.0 0.5 0 0 0.5 0.5 1 5.5 h 5.5\n"
              "ROBOTLASER1 0 -1.5 3.0 1.0 20 0.01 0 4 1 2 3 4 2 0.1 0.2 "
              "1.2 3.0 0.5 1.0 3.0 0.5 0 0 0.5 0.5 1 6.5 h 6.5\n");
  const hmt::Log log = read_log(p);
  ASSERT_EQ(log.steps.size(), 2u);
  EXPECT_FLOAT_EQ(log.steps[0].scan.angle_min, -1.5f);
  EXPECT_FLOAT_EQ(log.steps[0].scan.angle_increment, 1.0f);
  EXPECT_NEAR(log.steps[0].scan.sensor_pose.x, 0.2 * std::cos(0.5), 1e-9);
  EXPECT_NEAR(log.steps[0].scan.sensor_pose.y, -0.2 * std::sin(0.5), 1e-9);
  EXPECT_NEAR(log.steps[1].odometry_increment.norm(), 1.0, 1e-9);
  EXPECT_DOUBLE_EQ(log.steps[1].timestamp, 6.5);
}

}  // namespace
}  // namespace hmt::io

// Hostile but valid inputs through the application (issue 15 item 3): each
// is mapped without a crash, a hang or a nonsensical result, or refused with
// one clear error line and its exit code. The logs are CARMEN text made
// here: a robot driving along a 20 m x 8 m room, its scans ray-cast against
// the walls, before each case twists one thing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "hmt/common/error.h"
#include "hmt/io/tum.h"
#include "run_app.h"

namespace hmt::e2e {
namespace {
namespace fs = std::filesystem;

constexpr double kPi = 3.14159265358979323846;

struct Step {
  double x = 0.0, y = 0.0, theta = 0.0;  // odometry = true pose, unless twisted
  double t = 0.0;
  std::vector<double> ranges;
};

// Distance from (x, y) along `bearing` to the walls of [-5, 15] x [-4, 4].
double to_walls(double x, double y, double bearing) {
  const double dx = std::cos(bearing), dy = std::sin(bearing);
  double best = 1e9;
  if (dx > 1e-12) best = std::min(best, (15.0 - x) / dx);
  if (dx < -1e-12) best = std::min(best, (-5.0 - x) / dx);
  if (dy > 1e-12) best = std::min(best, (4.0 - y) / dy);
  if (dy < -1e-12) best = std::min(best, (-4.0 - y) / dy);
  return best;
}

std::vector<double> room_scan(double x, double y, double theta, int beams = 181) {
  std::vector<double> r(beams);
  for (int i = 0; i < beams; ++i)
    r[i] = to_walls(x, y, theta - kPi / 2 + kPi * i / (beams - 1));
  return r;
}

// `n` steps 0.1 m apart along the room's axis, one per second.
std::vector<Step> drive(int n) {
  std::vector<Step> steps(n);
  for (int k = 0; k < n; ++k) {
    steps[k].x = 0.1 * k;
    steps[k].t = 1000.0 + k;
    steps[k].ranges = room_scan(steps[k].x, 0.0, 0.0);
  }
  return steps;
}

std::string carmen(const std::vector<Step>& steps, int precision = 9) {
  std::string text = "# made by hostile_input_test\n";
  char num[64];
  for (const Step& s : steps) {
    text += "FLASER " + std::to_string(s.ranges.size());
    for (double r : s.ranges) {
      std::snprintf(num, sizeof num, " %.*g", precision, r);
      text += num;
    }
    std::snprintf(num, sizeof num, " %.9g %.9g %.9g", s.x, s.y, s.theta);
    text += std::string(num) + num;  // laser pose, then odometry: the same
    std::snprintf(num, sizeof num, " %.6f host %.6f\n", s.t, s.t);
    text += num;
  }
  return text;
}

void write(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

std::string last_line(const std::string& s) {
  std::string t = s;
  while (!t.empty() && t.back() == '\n') t.pop_back();
  const auto p = t.rfind('\n');
  return p == std::string::npos ? t : t.substr(p + 1);
}

class HostileInput : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = temp_dir(std::string("hostile_") +
                    ::testing::UnitTest::GetInstance()->current_test_info()->name());
  }

  // hmt-slam run on `log` (written into the test's folder), bounded in time
  // (a hang fails: `timeout` exits 124) and, after `shell_prefix` (e.g. a
  // ulimit), with the extra arguments.
  AppResult run_log(const std::string& log_text, const std::string& out = "out",
                    const std::string& extra = "", const std::string& shell_prefix = "") {
    write(dir_ + "/in.log", log_text);
    const std::string cmd = std::string("cd '") + HMT_SOURCE_DIR + "' && " + shell_prefix +
                            "timeout 600 '" + HMT_SLAM_BIN +
                            "' run --config config/default.ini --quiet --input '" + dir_ +
                            "/in.log' --out '" + dir_ + "/" + out + "' " + extra + " </dev/null >'" +
                            dir_ + "/stdout.txt' 2>'" + dir_ + "/stderr.txt'";
    const int status = std::system(cmd.c_str());
    AppResult r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = slurp(dir_ + "/stdout.txt");
    r.err = slurp(dir_ + "/stderr.txt");
    return r;
  }

  // A run that worked: exit 0, one finite trajectory pose per scan, the map
  // image written (and, with `max_side` > 0, no larger than that in pixels:
  // a map blown up by a wild reading would not be).
  std::vector<io::StampedPose> expect_mapped(const AppResult& r, size_t scans,
                                             int max_side = 0) {
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("processed " + std::to_string(scans) + " scans"), std::string::npos)
        << r.out;
    std::vector<io::StampedPose> traj;
    try {
      traj = io::read_tum(dir_ + "/out/trajectory.tum");
    } catch (const std::exception& e) {
      ADD_FAILURE() << e.what();
    }
    EXPECT_EQ(traj.size(), scans);
    for (const auto& p : traj)
      EXPECT_TRUE(std::isfinite(p.pose.x) && std::isfinite(p.pose.y) &&
                  std::isfinite(p.pose.theta));
    const std::string png = slurp(dir_ + "/out/map.png");
    EXPECT_GT(png.size(), 24u);
    if (max_side > 0 && png.size() > 24) {
      // PNG: width and height, big-endian, at bytes 16 and 20.
      auto be32 = [&](size_t at) {
        return (uint32_t(uint8_t(png[at])) << 24) | (uint32_t(uint8_t(png[at + 1])) << 16) |
               (uint32_t(uint8_t(png[at + 2])) << 8) | uint32_t(uint8_t(png[at + 3]));
      };
      EXPECT_LE(be32(16), uint32_t(max_side));
      EXPECT_LE(be32(20), uint32_t(max_side));
    }
    return traj;
  }

  void expect_error(const AppResult& r, ExitCode code, const std::string& mention) {
    EXPECT_EQ(r.exit_code, static_cast<int>(code)) << r.err;
    const std::string line = last_line(r.err);
    EXPECT_EQ(line.rfind("hmt-slam: error: ", 0), 0u) << r.err;
    EXPECT_NE(line.find(mention), std::string::npos) << line;
  }

  std::string dir_;
};

// The room is 20 m x 8 m: at 5 cm a cell, its map is some 400 x 160 pixels
// plus margins; a wild reading or pose would make it far larger.
constexpr int kRoomMapSide = 1500;

TEST_F(HostileInput, HundredThousandBeamsPerScan) {
  std::vector<Step> steps = drive(3);
  for (Step& s : steps) s.ranges = room_scan(s.x, 0.0, 0.0, 100000);
  expect_mapped(run_log(carmen(steps, 5)), 3, kRoomMapSide);
  // One more is beyond any real scanner, and refused.
  steps.resize(1);
  steps[0].ranges = room_scan(0, 0, 0, 100001);
  expect_error(run_log(carmen(steps, 4)), ExitCode::kInput, "absurd beam count 100001");
}

// Every 7th beam of every scan reads `value`.
std::vector<Step> with_readings(double value) {
  std::vector<Step> steps = drive(40);
  for (Step& s : steps)
    for (size_t i = 0; i < s.ranges.size(); i += 7) s.ranges[i] = value;
  return steps;
}

TEST_F(HostileInput, RangesOf1e30AreNoReturnsLikeAnyLongReading) {
  // The log's longest readings are its no-return code (carmen.h): 1e30 m
  // maps exactly as 80 m does, and neither stretches the map.
  expect_mapped(run_log(carmen(with_readings(80.0))), 40, kRoomMapSide);
  const std::string png = slurp(dir_ + "/out/map.png");
  const std::string tum = slurp(dir_ + "/out/trajectory.tum");
  expect_mapped(run_log(carmen(with_readings(1e30))), 40, kRoomMapSide);
  EXPECT_EQ(slurp(dir_ + "/out/map.png"), png);
  EXPECT_EQ(slurp(dir_ + "/out/trajectory.tum"), tum);
  // Beyond a float, a reading is refused rather than made infinite.
  expect_error(run_log(carmen(with_readings(1e39))), ExitCode::kInput,
               "beyond what a float holds");
}

TEST_F(HostileInput, DenormalRangesAreNoReadingsLikeZero) {
  // 1e-40 m is a float denormal: a zero with rounding noise, not a
  // distance. It maps exactly as a zero reading (invalid) does.
  expect_mapped(run_log(carmen(with_readings(0.0))), 40, kRoomMapSide);
  const std::string png = slurp(dir_ + "/out/map.png");
  const std::string tum = slurp(dir_ + "/out/trajectory.tum");
  expect_mapped(run_log(carmen(with_readings(1e-40))), 40, kRoomMapSide);
  EXPECT_EQ(slurp(dir_ + "/out/map.png"), png);
  EXPECT_EQ(slurp(dir_ + "/out/trajectory.tum"), tum);
}

TEST_F(HostileInput, OneScanRepeatedTenThousandTimes) {
  std::vector<Step> steps(10000);
  const std::vector<double> scan = room_scan(0, 0, 0);
  for (size_t k = 0; k < steps.size(); ++k) {
    steps[k].t = 1000.0 + 0.1 * double(k);
    steps[k].ranges = scan;
  }
  const auto traj = expect_mapped(run_log(carmen(steps, 6)), 10000, kRoomMapSide);
  ASSERT_FALSE(traj.empty());
  EXPECT_LT(std::hypot(traj.back().pose.x, traj.back().pose.y), 0.2);
}

TEST_F(HostileInput, TimestampsBackwardsOrAllZeroMapAsInOrder) {
  // The step order is the line order (carmen.h): the clock changes nothing.
  std::vector<Step> steps = drive(40);
  expect_mapped(run_log(carmen(steps)), 40, kRoomMapSide);
  const std::string png = slurp(dir_ + "/out/map.png");
  for (size_t k = 0; k < steps.size(); ++k) steps[k].t = 5000.0 - 7.0 * double(k);
  expect_mapped(run_log(carmen(steps)), 40, kRoomMapSide);
  EXPECT_EQ(slurp(dir_ + "/out/map.png"), png) << "backwards timestamps";
  for (Step& s : steps) s.t = 0.0;
  expect_mapped(run_log(carmen(steps)), 40, kRoomMapSide);
  EXPECT_EQ(slurp(dir_ + "/out/map.png"), png) << "all-zero timestamps";
}

TEST_F(HostileInput, OdometryJumpOfOneKilometre) {
  // The odometry leaps 1 km ahead at step 20 while the scans say the robot
  // drove on: believed, it would make a map 1 km wide; it is refused, naming
  // the step.
  std::vector<Step> steps = drive(40);
  for (size_t k = 20; k < steps.size(); ++k) steps[k].x += 1000.0;
  expect_error(run_log(carmen(steps)), ExitCode::kInput,
               "step 20: the odometry moves the robot 1e+03 m in one step");
  // A log whose first steps are skipped is checked from where it starts.
  expect_mapped(run_log(carmen(steps), "out", "--set input.first_step=21"), 19, kRoomMapSide);
}

TEST_F(HostileInput, RobotThatNeverMoves) {
  std::vector<Step> steps(300);
  for (size_t k = 0; k < steps.size(); ++k) {
    steps[k].t = 1000.0 + double(k);
    steps[k].ranges = room_scan(0, 0, 0);
    // Real sensor noise, so that the scans are not all the same bytes.
    for (size_t i = 0; i < steps[k].ranges.size(); ++i)
      steps[k].ranges[i] += 0.01 * std::sin(double(k * 31 + i * 7));
  }
  const auto traj = expect_mapped(run_log(carmen(steps)), 300, kRoomMapSide);
  ASSERT_FALSE(traj.empty());
  EXPECT_LT(std::hypot(traj.back().pose.x, traj.back().pose.y), 0.2);
  EXPECT_LT(std::abs(traj.back().pose.theta), 0.05);
}

TEST_F(HostileInput, OdometryFrozenWhileTheRobotTurns) {
  // The wheels' counts stop at step 19 while the robot turns on the spot:
  // read as standing still, every later scan would be placed at step 19's
  // pose (a map of the first scans, exit 0). It is refused, naming where.
  std::vector<Step> steps = drive(40);
  for (size_t k = 20; k < steps.size(); ++k) {
    const double turned = 0.1 * double(k - 19);
    steps[k].ranges = room_scan(steps[19].x, 0.0, turned);
    steps[k].x = steps[19].x;  // the odometry: frozen
  }
  expect_error(run_log(carmen(steps)), ExitCode::kInput, "since step 19, but the odometry");
  // The same turn with the odometry counting it is mapped.
  for (size_t k = 20; k < steps.size(); ++k) steps[k].theta = 0.1 * double(k - 19);
  expect_mapped(run_log(carmen(steps)), 40, kRoomMapSide);
}

TEST_F(HostileInput, OdometryTurningTheWrongWay) {
  // The robot drives 1 m, then turns on the spot, 0.2 rad a step; its
  // odometry's heading mirrored (a left-handed frame), or in degrees, or its
  // laser upside down. The
  // matches would start half a radian or more off at every turn, beyond the
  // heading search: a garbage map with exit 0. Refused, naming the problem.
  std::vector<Step> steps = drive(70);
  for (size_t k = 10; k < steps.size(); ++k) {
    steps[k].x = steps[9].x;
    steps[k].theta = 0.2 * double(k - 9);
    steps[k].ranges = room_scan(steps[k].x, 0.0, steps[k].theta);
  }
  expect_mapped(run_log(carmen(steps)), 70, kRoomMapSide);
  std::vector<Step> mirrored = steps;
  for (Step& s : mirrored) s.theta = -s.theta;
  expect_error(run_log(carmen(mirrored)), ExitCode::kInput,
               "the odometry's turns disagree with the laser's at 10 of the first 10");
  // In degrees, a step's 0.2 rad reads as 11.46 rad: -1.11 rad once wrapped.
  std::vector<Step> degrees = steps;
  for (Step& s : degrees) s.theta *= 180.0 / kPi;
  expect_error(run_log(carmen(degrees)), ExitCode::kInput, "headings in degrees");
  // A laser upside down: its beams run from left to right.
  std::vector<Step> upside_down = steps;
  for (Step& s : upside_down) std::reverse(s.ranges.begin(), s.ranges.end());
  expect_error(run_log(carmen(upside_down)), ExitCode::kInput, "a laser mounted upside down");
}

TEST_F(HostileInput, LogOfOnlyOdometry) {
  std::string text;
  for (int k = 0; k < 50; ++k)
    text += "ODOM " + std::to_string(0.1 * k) + " 0 0 0.1 0 0 " + std::to_string(1000 + k) +
            " host " + std::to_string(1000 + k) + "\n";
  expect_error(run_log(text), ExitCode::kInput, "holds no laser scans");
}

TEST_F(HostileInput, OutputPathIsAFile) {
  write(dir_ + "/taken", "a file, not a folder");
  expect_error(run_log(carmen(drive(5)), "taken"), ExitCode::kOutput, "taken");
  EXPECT_EQ(slurp(dir_ + "/taken"), "a file, not a folder");
}

TEST_F(HostileInput, OutputOnAFullDisk) {
  // ulimit -f: no file may grow past 64 KB, as on a disk that fills up
  // while the outputs are written. The run must say which output failed
  // and leave no partial file behind.
  const AppResult r = run_log(carmen(drive(40)), "out", "", "ulimit -f 64 && ");
  expect_error(r, ExitCode::kOutput, dir_ + "/out/");
  if (fs::exists(dir_ + "/out")) {
    for (const auto& e : fs::directory_iterator(dir_ + "/out"))
      EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
  }
}

}  // namespace
}  // namespace hmt::e2e

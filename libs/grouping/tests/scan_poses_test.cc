#include "hmt/grouping/scan_poses.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "hmt/common/error.h"
#include "hmt_test/scratch.h"

namespace hmt::grouping {
namespace {
namespace fs = std::filesystem;

// A file removed if the test passes.
std::string temp_file(const std::string& name, const std::string& text,
                      bool gzip = false) {
  const fs::path p = scratch::track(fs::temp_directory_path() /
                                    ("hmt_grouping_" + std::to_string(::getpid()) + "_" + name));
  if (gzip) {
    gzFile f = gzopen(p.c_str(), "wb");
    gzwrite(f, text.data(), static_cast<unsigned>(text.size()));
    gzclose(f);
  } else {
    std::ofstream(p) << text;
  }
  return p.string();
}

Log log_with_stamps(const std::vector<double>& stamps) {
  Log log;
  log.source = "test.log";
  for (double t : stamps) {
    LogStep s;
    s.timestamp = t;
    s.has_odometry = !log.steps.empty();
    s.odometry_increment = Pose2D(1.0, 0.0, M_PI / 2);
    log.steps.push_back(s);
  }
  return log;
}

TEST(ScanPoses, OdometryAccumulatesIncrementsFromTheOrigin) {
  const Log log = log_with_stamps({0, 1, 2, 3});
  const ScanPoses p = odometry_poses(log);
  ASSERT_EQ(p.size(), 4u);
  EXPECT_EQ(p.missing, 0u);
  EXPECT_NEAR(p.pose[0].x, 0.0, 1e-12);
  // Three unit steps, each ending with a left turn of 90 degrees:
  // (1,0,90), (1,1,180), (0,1,-90).
  EXPECT_NEAR(p.pose[2].x, 1.0, 1e-12);
  EXPECT_NEAR(p.pose[2].y, 1.0, 1e-12);
  EXPECT_NEAR(p.pose[3].x, 0.0, 1e-12);
  EXPECT_NEAR(p.pose[3].y, 1.0, 1e-12);
  EXPECT_NEAR(p.pose[3].theta, -M_PI / 2, 1e-12);
  EXPECT_EQ(odometry_poses(log, 2).size(), 2u);
}

TEST(ScanPoses, ReadsReferenceFormatPlainAndGzip) {
  const std::string text =
      "# timestamp x y theta\n\n1.5 2 3 0.5\n2.5 4 5 -0.25\n";
  for (bool gz : {false, true}) {
    const auto t = read_pose_file(temp_file(gz ? "ref.txt.gz" : "ref.txt", text, gz));
    ASSERT_EQ(t.size(), 2u);
    EXPECT_DOUBLE_EQ(t[1].timestamp, 2.5);
    EXPECT_DOUBLE_EQ(t[1].pose.x, 4.0);
    EXPECT_DOUBLE_EQ(t[1].pose.theta, -0.25);
  }
}

TEST(ScanPoses, ReadsTumByItsFieldCount) {
  const double h = 0.3 / 2;
  char line[200];
  std::snprintf(line, sizeof line, "7.0 1 2 0 0 0 %.12f %.12f\n", std::sin(h),
                std::cos(h));
  const auto t = read_pose_file(temp_file("traj.tum", line));
  ASSERT_EQ(t.size(), 1u);
  EXPECT_NEAR(t[0].pose.theta, 0.3, 1e-9);
  EXPECT_DOUBLE_EQ(t[0].pose.y, 2.0);
}

TEST(ScanPoses, BadFilesNameTheFileAndLine) {
  const auto expect_input_error = [](const std::string& path, const std::string& what) {
    try {
      read_pose_file(path);
      ADD_FAILURE() << "no error for " << path;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  expect_input_error(temp_file("five.txt", "1 2 3 4 5\n"), "line 1");
  expect_input_error(temp_file("mixed.txt", "1 2 3 4\n2 3 4\n"), "line 2");
  expect_input_error(temp_file("nan.txt", "# c\n1 2 nan 4\n"), "field 3");
  expect_input_error(temp_file("empty.txt", "# only a comment\n"), "holds no pose");
  expect_input_error("/nonexistent/poses.txt", "does not exist");
}

TEST(ScanPoses, MatchesNearestTimestampWithinTolerance) {
  const Log log = log_with_stamps({1.000, 2.000, 3.000, 4.000});
  std::vector<io::StampedPose> traj = {
      {4.004, Pose2D(4, 0, 0)},   // 4.000: 4 ms away
      {1.009, Pose2D(1, 0, 0)},   // 1.000: 9 ms (unsorted input)
      {2.020, Pose2D(2, 0, 0)},   // 2.000: 20 ms, too far
      {2.995, Pose2D(30, 0, 0)},  // 3.000: 5 ms before ...
      {3.005, Pose2D(31, 0, 0)},  // ... and 5 ms after: the earlier wins
  };
  const ScanPoses p = match_poses(log, traj, 0.01, "traj");
  ASSERT_EQ(p.size(), 4u);
  EXPECT_EQ(p.missing, 1u);
  EXPECT_TRUE(p.has_pose[0]);
  EXPECT_FALSE(p.has_pose[1]);
  EXPECT_DOUBLE_EQ(p.pose[0].x, 1.0);
  EXPECT_DOUBLE_EQ(p.pose[2].x, 30.0);
  EXPECT_DOUBLE_EQ(p.pose[3].x, 4.0);
  EXPECT_EQ(p.source, "traj");
}

TEST(ScanPoses, NoMatchAtAllIsAnInputError) {
  const Log log = log_with_stamps({1.0, 2.0});
  EXPECT_THROW(match_poses(log, {{100.0, Pose2D()}}, 0.01, "other"), InputError);
}

}  // namespace
}  // namespace hmt::grouping

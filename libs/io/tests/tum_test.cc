#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>

#include "hmt/io/tum.h"
#include "io_test_util.h"

namespace hmt::io {
namespace {

using namespace testing_util;

TEST(TumConversion, WriteReadRoundTrip) {
  std::vector<StampedPose> traj;
  for (int i = 0; i < 50; ++i) {
    const double th = -M_PI + 0.13 * i;  // includes angles near +-pi
    traj.push_back({1137834225.713386 + 0.25 * i,
                    Pose2D(-3.5 + 0.71 * i, 12.25 - 0.3 * i, wrap_angle(th))});
  }
  traj.push_back({1.5, Pose2D(0, 0, M_PI)});
  const std::string p = scratch_dir() + "/traj.tum";
  write_tum(p, traj);
  const auto back = read_tum(p);
  ASSERT_EQ(back.size(), traj.size());
  for (size_t i = 0; i < traj.size(); ++i) {
    EXPECT_NEAR(back[i].timestamp, traj[i].timestamp, 1e-6);
    EXPECT_NEAR(back[i].pose.x, traj[i].pose.x, 1e-6);
    EXPECT_NEAR(back[i].pose.y, traj[i].pose.y, 1e-6);
    EXPECT_NEAR(wrap_angle(back[i].pose.theta - traj[i].pose.theta), 0.0,
                1e-8);
  }
}

TEST(TumConversion, LineFormat) {
  const std::string p = scratch_dir() + "/one.tum";
  write_tum(p, {{12.5, Pose2D(1.0, -2.0, M_PI / 2)}});
  EXPECT_EQ(read_bytes(p),
            "12.500000 1.000000 -2.000000 0.000000 0.000000000 0.000000000 "
            "0.707106781 0.707106781\n");
}

TEST(TumConversion, EmptyTrajectory) {
  const std::string p = scratch_dir() + "/empty.tum";
  write_tum(p, {});
  EXPECT_TRUE(std::filesystem::exists(p));
  EXPECT_TRUE(read_tum(p).empty());
}

TEST(TumConversion, CommentsBlankLinesAndGeneralQuaternions) {
  const std::string p = scratch_dir() + "/c.tum";
  // A yaw of 90 deg about z, not normalised, and one with tiny roll/pitch.
  write_bytes(p,
              "# timestamp x y z qx qy qz qw\n\n"
              "1.0 1 2 0.5 0 0 2 2\n"
              "  2.0\t3 4 0 0.001 -0.002 0.3826834 0.9238795\r\n");
  const auto t = read_tum(p);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_NEAR(t[0].pose.theta, M_PI / 2, 1e-12);
  EXPECT_DOUBLE_EQ(t[0].pose.x, 1.0);
  EXPECT_NEAR(t[1].pose.theta, M_PI / 4, 1e-2);
  EXPECT_DOUBLE_EQ(t[1].timestamp, 2.0);
}

TEST(TumConversion, QuaternionsOfExtremeMagnitude) {
  // Squaring 1e308 overflows and 1e-300 underflows: the rotation must come
  // out all the same (90 deg about z both times).
  const std::string p = scratch_dir() + "/big.tum";
  write_bytes(p, "1 0 0 0 0 0 1e308 1e308\n2 0 0 0 0 0 1e-300 1e-300\n");
  expect_input_error([&] { read_tum(p); }, {p, "line 2", "quaternion is zero"});
  write_bytes(p, "1 0 0 0 0 0 1e308 1e308\n2 0 0 0 0 0 -3e307 -3e307\n");
  const auto t = read_tum(p);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_NEAR(t[0].pose.theta, M_PI / 2, 1e-12);
  EXPECT_NEAR(t[1].pose.theta, M_PI / 2, 1e-12);
}

TEST(TumConversion, MalformedLines) {
  const std::string p = scratch_dir() + "/bad.tum";
  const std::string good = "1.0 0 0 0 0 0 0 1\n";
  write_bytes(p, good + "# c\n2.0 0 0 0 0 0 1\n");
  expect_input_error([&] { read_tum(p); },
                     {p, "line 3", "expected 8 fields", "found 7"});
  write_bytes(p, good + "2.0 0 0 0 0 0 0 1 9\n");
  expect_input_error([&] { read_tum(p); }, {p, "line 2", "found 9"});
  write_bytes(p, good + good + "3.0 0 abc 0 0 0 0 1\n");
  expect_input_error([&] { read_tum(p); }, {p, "line 3", "field 3", "'abc'"});
  write_bytes(p, "nan 0 0 0 0 0 0 1\n");
  expect_input_error([&] { read_tum(p); }, {p, "line 1", "field 1"});
  write_bytes(p, "1 0 0 0 0 0 0 0\n");
  expect_input_error([&] { read_tum(p); }, {p, "line 1", "quaternion"});
}

TEST(TumConversion, NonFinitePoseIsNotWritten) {
  const std::string p = scratch_dir() + "/nan.tum";
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(write_tum(p, {{1.0, Pose2D(0, 0, 0)}, {2.0, Pose2D(nan, 0, 0)}}),
               hmt::OutputError);
  EXPECT_FALSE(std::filesystem::exists(p));
}

}  // namespace
}  // namespace hmt::io

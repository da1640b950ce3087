// ROS bags in: bags written from the embedded Edmonton CARMEN log (odometry
// as nav_msgs/Odometry, or as /tf transforms; the laser's mounting on
// /tf_static) read back as the log itself, and every kind of bad bag ends in
// a one-line hmt::InputError naming the problem.
#include <gtest/gtest.h>

#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>
#include <std_msgs/String.h>
#include <tf2_msgs/TFMessage.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>

#include "hmt/io/bag_writer.h"
#include "hmt/io/carmen.h"
#include "hmt/io/log_reader.h"
#include "hmt/io/log_stream.h"
#include "hmt/io/rosbag.h"
#include "io_test_util.h"

// tf's tfMessage: tf2_msgs/TFMessage under tf's own name, as older bags
// have it on /tf.
struct TfV1Message : tf2_msgs::TFMessage {};

namespace ros::message_traits {
template <>
struct MD5Sum<TfV1Message> : MD5Sum<tf2_msgs::TFMessage> {};
template <>
struct DataType<TfV1Message> {
  static const char* value() { return "tf/tfMessage"; }
  static const char* value(const TfV1Message&) { return value(); }
};
template <>
struct Definition<TfV1Message> : Definition<tf2_msgs::TFMessage> {};
}  // namespace ros::message_traits
namespace ros::serialization {
template <>
struct Serializer<TfV1Message> : Serializer<tf2_msgs::TFMessage> {};
}  // namespace ros::serialization

namespace hmt::io {
namespace {

using namespace testing_util;

// The Edmonton log and a bag written from it with its own odometry poses.
// Edmonton's laser sits at the robot's origin; the log is given a mounting
// off it (turned too) so that /tf_static carries something.
struct EdmontonBag {
  Log carmen;
  std::string bag;
};

EdmontonBag edmonton_bag(const std::string& dir, BagWriteOptions o = {}) {
  std::vector<Pose2D> odom;
  EdmontonBag out;
  out.carmen = read_carmen(edmonton_path(), &odom);
  for (LogStep& s : out.carmen.steps) s.scan.sensor_pose = Pose2D(0.12, -0.03, 0.05);
  out.bag = dir + "/edmonton.bag";
  write_bag(out.carmen, out.bag, o, &odom);
  return out;
}

// Bit for bit but the timestamps, which a bag holds to the nanosecond.
void expect_same_as_carmen(Log from_bag, const Log& carmen) {
  EXPECT_GT(carmen.steps.size(), 300u);
  from_bag.source = carmen.source;
  expect_identical_logs(from_bag, carmen, /*time_tolerance=*/1e-6);
}

TEST(RosBag, OdometryTopicReadsAsTheCarmenLog) {
  const auto e = edmonton_bag(scratch_dir());
  EXPECT_EQ(detect_log_format(e.bag), LogFormat::kRosBag);
  const Log log = read_log(e.bag);
  EXPECT_EQ(log.source, e.bag);
  expect_same_as_carmen(log, e.carmen);
}

TEST(RosBag, TfOdometryReadsAsTheCarmenLog) {
  BagWriteOptions o;
  o.odometry = BagWriteOptions::Odometry::kTf;
  const auto e = edmonton_bag(scratch_dir(), o);
  expect_same_as_carmen(read_log(e.bag), e.carmen);
}

TEST(RosBag, OlderBagsTfMessages) {
  // The Edmonton bag with odometry on /tf, rewritten with tf's tfMessage.
  BagWriteOptions o;
  o.odometry = BagWriteOptions::Odometry::kTf;
  const std::string dir = scratch_dir();
  const auto e = edmonton_bag(dir, o);
  const std::string p = dir + "/tf1.bag";
  {
    rosbag::Bag in, out;
    in.open(e.bag, rosbag::bagmode::Read);
    out.open(p, rosbag::bagmode::Write);
    size_t transforms = 0;
    for (const rosbag::MessageInstance& m : rosbag::View(in)) {
      if (auto tf = m.instantiate<tf2_msgs::TFMessage>()) {
        TfV1Message v1;
        v1.transforms = tf->transforms;
        out.write(m.getTopic(), m.getTime(), v1);
        ++transforms;
      } else {
        out.write(m.getTopic(), m.getTime(), m);
      }
    }
    EXPECT_GT(transforms, 300u);
  }
  rosbag::Bag check;
  check.open(p, rosbag::bagmode::Read);
  for (const rosbag::ConnectionInfo* c : rosbag::View(check).getConnections()) {
    if (c->topic == "/tf" || c->topic == "/tf_static") {
      EXPECT_EQ(c->datatype, "tf/tfMessage");
    }
  }
  expect_same_as_carmen(read_log(p), e.carmen);
}

TEST(RosBag, OtherFrameAndTopicNamesThroughTheOptions) {
  BagWriteOptions o;
  o.odometry = BagWriteOptions::Odometry::kTf;
  o.odom_frame = "world_odom";
  o.base_frame = "robot";
  o.scan_topic = "/front/scan";
  const auto e = edmonton_bag(scratch_dir(), o);
  expect_input_error([&] { read_log(e.bag); },
                     {e.bag, "no odometry", "'odom'", "'base_link'", "robot", "world_odom"});
  BagOptions b;
  b.odom_frame = "world_odom";
  b.base_frame = "/robot";  // tf1 names
  b.scan_topic = "front/scan";
  expect_same_as_carmen(read_log(e.bag, b), e.carmen);
}

TEST(RosBag, LaserPoseOptionReplacesTf) {
  const auto e = edmonton_bag(scratch_dir());
  BagOptions b;
  b.has_laser_pose = true;
  b.laser_pose = Pose2D(0.5, -0.25, 0.1);
  const Log log = read_log(e.bag, b);
  ASSERT_EQ(log.steps.size(), e.carmen.steps.size());
  for (const LogStep& s : log.steps) {
    EXPECT_EQ(s.scan.sensor_pose.x, 0.5);
    EXPECT_EQ(s.scan.sensor_pose.y, -0.25);
    EXPECT_NEAR(s.scan.sensor_pose.theta, 0.1, 1e-15);
  }
}

TEST(RosBag, ConvertsToTheSameRawlogsAsTheLog) {
  const std::string dir = scratch_dir();
  const auto e = edmonton_bag(dir);
  write_rawlog(read_log(e.bag), dir + "/from_bag.rawlog", RawlogFormat::kObservationsOnly);
  write_rawlog(e.carmen, dir + "/from_log.rawlog", RawlogFormat::kObservationsOnly);
  Log a = read_rawlog(dir + "/from_bag.rawlog");
  const Log b = read_rawlog(dir + "/from_log.rawlog");
  a.source = b.source;
  // Rawlogs keep time to 100 ns.
  expect_identical_logs(a, b, 2e-7);
}

// --- bags written message by message ------------------------------------

sensor_msgs::LaserScan scan_msg(double t, const std::string& frame = "base_link") {
  sensor_msgs::LaserScan s;
  s.header.stamp = ros::Time(t);
  s.header.frame_id = frame;
  s.angle_min = -1.0f;
  s.angle_increment = 0.5f;
  s.angle_max = 1.0f;
  s.range_min = 0.1f;
  s.range_max = 10.0f;
  s.ranges = {1.0f, 2.0f, 3.0f, 4.0f, 5.0f};
  return s;
}

nav_msgs::Odometry odom_msg(double t, double x) {
  nav_msgs::Odometry o;
  o.header.stamp = ros::Time(t);
  o.header.frame_id = "odom";
  o.child_frame_id = "base_link";
  o.pose.pose.position.x = x;
  o.pose.pose.orientation.w = 1.0;
  return o;
}

// A bag of scans at t = 10, 11, 12 and odometry from 9.5 to 12.5 (x = t),
// written by `fill` on top of that when given.
std::string small_bag(const std::string& path,
                      const std::function<void(rosbag::Bag&)>& fill = {},
                      bool scans = true, bool odometry = true) {
  rosbag::Bag bag;
  bag.open(path, rosbag::bagmode::Write);
  for (double t = 9.5; t <= 12.6; t += 0.5) {
    if (odometry) bag.write("/odom", ros::Time(t), odom_msg(t, t));
    if (scans && t >= 10.0 && t <= 12.0 && std::fmod(t, 1.0) == 0.0)
      bag.write("/scan", ros::Time(t), scan_msg(t));
  }
  if (fill) fill(bag);
  bag.close();
  return path;
}

TEST(RosBag, BeamsFollowRosConventions) {
  const std::string p = scratch_dir() + "/beams.bag";
  rosbag::Bag bag;
  bag.open(p, rosbag::bagmode::Write);
  bag.write("/odom", ros::Time(1.0), odom_msg(1.0, 0.0));
  auto s = scan_msg(1.0);
  const float inf = std::numeric_limits<float>::infinity();
  s.ranges = {0.05f, 0.1f, 10.0f, 10.5f, inf, -inf, std::nanf(""), 0.0f, 3.0f};
  s.angle_increment = -0.25f;  // clockwise: reversed on reading
  s.angle_min = 1.0f;
  bag.write("/scan", ros::Time(1.0), s);
  bag.close();
  const Log log = read_log(p);
  ASSERT_EQ(log.steps.size(), 1u);
  const LaserScan& out = log.steps[0].scan;
  EXPECT_FLOAT_EQ(out.angle_min, -1.0f);
  EXPECT_FLOAT_EQ(out.angle_increment, 0.25f);
  EXPECT_EQ(out.max_range, std::nextafter(10.0f, inf));
  // Reversed order: 3, 0, nan, -inf, inf, 10.5, 10, 0.1, 0.05.
  const std::vector<uint8_t> valid = {1, 0, 0, 0, 0, 0, 1, 1, 0};
  const std::vector<float> ranges = {3.0f, 0.0f, 0.0f, 0.0f, out.max_range, 10.5f, 10.0f, 0.1f, 0.05f};
  EXPECT_EQ(out.valid, valid);
  EXPECT_EQ(out.ranges, ranges);
}

// Odometry at 0 and 2 s (x from 0 to 2 m); the scans at 0.5 (x = 0.5 m) and
// 1.5 s (1.5 m) and one at 3 s, after the last odometry: left out.
void write_scans_past_the_odometry(const std::string& p) {
  rosbag::Bag bag;
  bag.open(p, rosbag::bagmode::Write);
  bag.write("/odom", ros::Time(0.001), odom_msg(0.001, 0.0));
  bag.write("/odom", ros::Time(2.001), odom_msg(2.001, 2.0));
  for (double t : {0.501, 1.501, 3.001}) bag.write("/scan", ros::Time(t), scan_msg(t));
  bag.close();
}

TEST(RosBag, OdometryIsInterpolatedAtTheScanStamps) {
  const std::string p = scratch_dir() + "/interp.bag";
  write_scans_past_the_odometry(p);
  const Log log = read_log(p);
  ASSERT_EQ(log.steps.size(), 2u);
  EXPECT_FALSE(log.steps[0].has_odometry);
  EXPECT_TRUE(log.steps[1].has_odometry);
  EXPECT_NEAR(log.steps[1].odometry_increment.x, 1.0, 1e-9);
  EXPECT_NEAR(log.steps[1].timestamp, 1.501, 1e-9);
}

TEST(RosBag, SeveralScanTopicsMustBeNamed) {
  const std::string p = small_bag(scratch_dir() + "/two.bag", [](rosbag::Bag& b) {
    b.write("/rear_scan", ros::Time(11.0), scan_msg(11.0));
  });
  expect_input_error([&] { read_log(p); },
                     {p, "several sensor_msgs/LaserScan topics", "/rear_scan", "/scan",
                      "[input] scan_topic"});
  BagOptions o;
  o.scan_topic = "/rear_scan";
  EXPECT_EQ(read_log(p, o).steps.size(), 1u);
  o.scan_topic = "/scan";
  EXPECT_EQ(read_log(p, o).steps.size(), 3u);
  o.scan_topic = "/nothing";
  expect_input_error([&] { read_log(p, o); }, {p, "no topic '/nothing'", "/rear_scan, /scan"});
  o.scan_topic = "/odom";
  expect_input_error([&] { read_log(p, o); },
                     {p, "'/odom'", "is nav_msgs/Odometry, not sensor_msgs/LaserScan"});
}

TEST(RosBag, NoScanTopic) {
  const std::string p = small_bag(scratch_dir() + "/noscan.bag", [](rosbag::Bag& b) {
    std_msgs::String s;
    s.data = "hello";
    b.write("/chatter", ros::Time(10.0), s);
  }, /*scans=*/false);
  expect_input_error([&] { read_log(p); },
                     {p, "no sensor_msgs/LaserScan topic", "/chatter (std_msgs/String)",
                      "/odom (nav_msgs/Odometry)"});
}

TEST(RosBag, NoOdometryAtAll) {
  const std::string p = small_bag(scratch_dir() + "/noodom.bag", {}, true, false);
  expect_input_error([&] { read_log(p); },
                     {p, "no odometry", "no nav_msgs/Odometry topic", "'odom'", "'base_link'"});
  BagOptions o;
  o.odom_topic = "tf";  // even with an Odometry topic
  const std::string q = small_bag(scratch_dir() + "/odom_but_tf.bag");
  expect_input_error([&] { read_log(q, o); }, {q, "no odometry"});
  o.odom_topic = "/scan";
  expect_input_error([&] { read_log(q, o); }, {q, "is sensor_msgs/LaserScan, not nav_msgs/Odometry"});
}

TEST(RosBag, SeveralOdometryTopicsMustBeNamed) {
  const std::string p = small_bag(scratch_dir() + "/twoodom.bag", [](rosbag::Bag& b) {
    b.write("/wheel_odom", ros::Time(11.0), odom_msg(11.0, 0.0));
  });
  expect_input_error([&] { read_log(p); },
                     {p, "several nav_msgs/Odometry topics", "/odom, /wheel_odom",
                      "[input] odom_topic"});
  BagOptions o;
  o.odom_topic = "/odom";
  EXPECT_EQ(read_log(p, o).steps.size(), 3u);
}

TEST(RosBag, NoScanWithinTheOdometry) {
  const std::string p = scratch_dir() + "/late.bag";
  rosbag::Bag bag;
  bag.open(p, rosbag::bagmode::Write);
  bag.write("/odom", ros::Time(1.0), odom_msg(1.0, 0.0));
  bag.write("/odom", ros::Time(2.0), odom_msg(2.0, 0.0));
  bag.write("/scan", ros::Time(5.0), scan_msg(5.0));
  bag.close();
  expect_input_error([&] { read_log(p); },
                     {p, "none of the 1 scans on '/scan'", "outside the span", "/odom"});
}

TEST(RosBag, NoLaserMounting) {
  const std::string p = small_bag(scratch_dir() + "/nomount.bag", [](rosbag::Bag& b) {
    b.write("/laser_scan", ros::Time(11.0), scan_msg(11.0, "laser"));
  });
  BagOptions o;
  o.scan_topic = "/laser_scan";
  expect_input_error([&] { read_log(p, o); },
                     {p, "no laser mounting", "'base_link'", "'laser'", "[input] laser_pose"});
}

TEST(RosBag, TiltedLaser) {
  const std::string p = small_bag(scratch_dir() + "/tilted.bag", [](rosbag::Bag& b) {
    b.write("/laser_scan", ros::Time(11.0), scan_msg(11.0, "laser"));
    tf2_msgs::TFMessage tf;
    geometry_msgs::TransformStamped t;
    t.header.stamp = ros::Time(10.0);
    t.header.frame_id = "base_link";
    t.child_frame_id = "laser";
    t.transform.rotation.y = std::sin(0.25);  // pitched 28.6 degrees
    t.transform.rotation.w = std::cos(0.25);
    tf.transforms.push_back(t);
    b.write("/tf_static", ros::Time(10.0), tf);
  });
  BagOptions o;
  o.scan_topic = "/laser_scan";
  expect_input_error([&] { read_log(p, o); }, {p, "tilted 28.6", "level laser"});
}

TEST(RosBag, UpsideDownLaserIsMirrored) {
  const std::string p = small_bag(scratch_dir() + "/flipped.bag", [](rosbag::Bag& b) {
    b.write("/laser_scan", ros::Time(11.0), scan_msg(11.0, "laser"));
    tf2_msgs::TFMessage tf;
    geometry_msgs::TransformStamped t;
    t.header.stamp = ros::Time(10.0);
    t.header.frame_id = "base_link";
    t.child_frame_id = "laser";
    t.transform.translation.x = 0.2;
    t.transform.rotation.x = 1.0;  // rolled 180 degrees
    tf.transforms.push_back(t);
    b.write("/tf_static", ros::Time(10.0), tf);
  });
  BagOptions o;
  o.scan_topic = "/laser_scan";
  const Log log = read_log(p, o);
  ASSERT_EQ(log.steps.size(), 1u);
  const LaserScan& s = log.steps[0].scan;
  // Beams at -1 .. +1 rad in the laser frame are at +1 .. -1 seen from
  // above: reversed so that bearings increase.
  EXPECT_FLOAT_EQ(s.angle_min, -1.0f);
  EXPECT_FLOAT_EQ(s.angle_increment, 0.5f);
  EXPECT_EQ(s.ranges, (std::vector<float>{5.0f, 4.0f, 3.0f, 2.0f, 1.0f}));
  EXPECT_DOUBLE_EQ(s.sensor_pose.x, 0.2);
  EXPECT_NEAR(s.sensor_pose.theta, 0.0, 1e-12);
}

TEST(RosBag, OtherMessageDefinition) {
  // The same bag with LaserScan's md5sum changed everywhere it is stored
  // (connection records in the chunk and in the index): as a bag recorded
  // with another definition of the message.
  const std::string dir = scratch_dir();
  const std::string good = small_bag(dir + "/good.bag");
  std::string bytes = read_bytes(good);
  const std::string md5 = ros::message_traits::MD5Sum<sensor_msgs::LaserScan>::value();
  const std::string other = "0123456789abcdef0123456789abcdef";
  size_t n = 0;
  for (size_t at = bytes.find(md5); at != std::string::npos; at = bytes.find(md5, at)) {
    bytes.replace(at, md5.size(), other);
    ++n;
  }
  ASSERT_GE(n, 2u);
  const std::string p = dir + "/other.bag";
  write_bytes(p, bytes);
  expect_input_error([&] { read_log(p); },
                     {p, "'/scan'", "another definition", other, md5});
}

TEST(RosBag, TruncatedBag) {
  const std::string dir = scratch_dir();
  const std::string bytes = read_bytes(edmonton_bag(dir).bag);
  for (const double part : {0.1, 0.5, 0.97}) {
    SCOPED_TRACE(part);
    const std::string p = dir + "/cut.bag";
    write_bytes(p, bytes.substr(0, static_cast<size_t>(bytes.size() * part)));
    expect_input_error([&] { read_log(p); }, {p, "ROS bag", "truncated or damaged"});
  }
}

TEST(RosBag, UnindexedBag) {
  // A recording that was interrupted: the header's index position is 0.
  const std::string dir = scratch_dir();
  std::string bytes = read_bytes(small_bag(dir + "/b.bag"));
  const std::string field = "index_pos=";
  const size_t at = bytes.find(field);
  ASSERT_NE(at, std::string::npos);
  bytes.replace(at + field.size(), 8, std::string(8, '\0'));
  const std::string p = dir + "/unindexed.bag";
  write_bytes(p, bytes);
  expect_input_error([&] { read_log(p); }, {p, "has no index", "rosbag reindex"});
}

TEST(RosBag, MissingPluginIsAnInputErrorNamingIt) {
  const std::string p = small_bag(scratch_dir() + "/b.bag");
  ASSERT_EQ(setenv("HMT_IO_ROSBAG_PLUGIN", "/nonexistent/libhmt_io_rosbag.so", 1), 0);
  expect_input_error([&] { read_log(p); },
                     {p, "ROS bag reader plugin cannot be loaded", "/nonexistent/libhmt_io_rosbag.so"});
  unsetenv("HMT_IO_ROSBAG_PLUGIN");
  EXPECT_EQ(read_log(p).steps.size(), 3u);
}

TEST(RosBag, GzipCompressedBag) {
  const std::string dir = scratch_dir();
  const std::string p = dir + "/edmonton.bag.gz";
  write_bytes(p, gzip_bytes(read_bytes(small_bag(dir + "/b.bag"))));
  expect_input_error([&] { read_log(p); }, {p, "gzip-compressed ROS bag", "decompress"});
}

TEST(RosBag, BadOdometryPose) {
  const std::string p = scratch_dir() + "/badq.bag";
  rosbag::Bag bag;
  bag.open(p, rosbag::bagmode::Write);
  auto o = odom_msg(1.0, 0.0);
  o.pose.pose.orientation.w = 0.0;  // the zero quaternion
  bag.write("/odom", ros::Time(1.0), o);
  bag.write("/scan", ros::Time(1.0), scan_msg(1.0));
  bag.close();
  expect_input_error([&] { read_log(p); }, {p, "message 0 on '/odom'", "not a rigid transform"});
}

TEST(RosBag, BadScans) {
  const std::string dir = scratch_dir();
  auto with_scan = [&](const std::string& name, sensor_msgs::LaserScan s) {
    const std::string p = dir + "/" + name + ".bag";
    rosbag::Bag bag;
    bag.open(p, rosbag::bagmode::Write);
    bag.write("/odom", ros::Time(1.0), odom_msg(1.0, 0.0));
    bag.write("/scan", ros::Time(1.0), s);
    bag.close();
    return p;
  };
  auto s = scan_msg(1.0);
  s.ranges.clear();
  std::string p = with_scan("empty", s);
  expect_input_error([&] { read_log(p); }, {p, "scan 0 on '/scan' has no beams"});
  s = scan_msg(1.0);
  s.angle_increment = 0.0f;
  p = with_scan("angles", s);
  expect_input_error([&] { read_log(p); }, {p, "no usable beam angles"});
  s = scan_msg(1.0);
  s.range_max = std::nanf("");
  p = with_scan("limits", s);
  expect_input_error([&] { read_log(p); }, {p, "range limits"});
}

// --- the bag as a stream ---------------------------------------------------

// The steps as open_log() hands them out, one at a time, checking that the
// stream knows its length from the start and reports its progress in order.
Log streamed(const std::string& path, const BagOptions& options = {}) {
  const std::unique_ptr<LogStream> s = open_log(path, options);
  const std::optional<size_t> total = s->total_steps();
  EXPECT_TRUE(total.has_value());
  EXPECT_EQ(s->fraction_read(), 0.0);
  Log log;
  log.source = s->source();
  LogStep step;
  double last = 0.0;
  while (s->next(step)) {
    log.steps.push_back(step);
    EXPECT_GE(s->fraction_read(), last);
    EXPECT_LE(s->fraction_read(), 1.0);
    last = s->fraction_read();
  }
  EXPECT_EQ(s->fraction_read(), 1.0);
  EXPECT_FALSE(s->next(step));  // stays at the end
  EXPECT_EQ(total.value_or(0), log.steps.size());
  return log;
}

TEST(RosBagStream, YieldsTheCarmenLogStepByStep) {
  for (const auto odometry : {BagWriteOptions::Odometry::kTopic, BagWriteOptions::Odometry::kTf}) {
    SCOPED_TRACE(odometry == BagWriteOptions::Odometry::kTf ? "tf" : "topic");
    BagWriteOptions o;
    o.odometry = odometry;
    const auto e = edmonton_bag(scratch_dir(), o);
    const Log log = streamed(e.bag);
    EXPECT_EQ(log.source, e.bag);
    expect_same_as_carmen(log, e.carmen);
    // The timestamps too, as a bag holds them (to the nanosecond).
    ASSERT_EQ(log.steps.size(), e.carmen.steps.size());
    for (size_t k = 0; k < log.steps.size(); ++k) {
      const double stamp = ros::Time(e.carmen.steps[k].timestamp).toSec();
      EXPECT_EQ(log.steps[k].timestamp, stamp);
      EXPECT_EQ(log.steps[k].scan.timestamp, stamp);
    }
  }
}

TEST(RosBagStream, KnowsItsLengthWithScansLeftOut) {
  const std::string p = scratch_dir() + "/left_out.bag";
  write_scans_past_the_odometry(p);
  const auto s = open_log(p);
  EXPECT_EQ(s->total_steps(), 2u);
  LogStep step;
  ASSERT_TRUE(s->next(step));
  ASSERT_TRUE(s->next(step));
  EXPECT_LT(s->fraction_read(), 1.0);  // the third message is not read yet
  EXPECT_FALSE(s->next(step));
  EXPECT_EQ(s->fraction_read(), 1.0);
  expect_identical_logs(streamed(p), read_log(p));
}

// What the reader refuses is found by the first pass: open_log() throws,
// before any step, even for the last scan of the bag.
TEST(RosBagStream, BadScansFailBeforeTheFirstStep) {
  const std::string p = scratch_dir() + "/bad_last.bag";
  rosbag::Bag bag;
  bag.open(p, rosbag::bagmode::Write);
  bag.write("/odom", ros::Time(1.0), odom_msg(1.0, 0.0));
  bag.write("/odom", ros::Time(3.0), odom_msg(3.0, 2.0));
  for (double t : {1.0, 1.5, 2.0}) bag.write("/scan", ros::Time(t), scan_msg(t));
  auto last = scan_msg(2.5);
  last.ranges.clear();
  bag.write("/scan", ros::Time(2.5), last);
  bag.close();
  expect_input_error([&] { open_log(p); }, {p, "scan 3 on '/scan' has no beams"});
}

TEST(RosBagStream, ABagChangedBetweenThePassesIsAnError) {
  const std::string dir = scratch_dir();
  const std::string p = dir + "/changing.bag";
  // Scans at 10, `second` and 12 s, odometry from 9.5 to 12.5 s.
  auto write = [&](double second) {
    rosbag::Bag bag;
    bag.open(p, rosbag::bagmode::Write);
    for (double t = 9.5; t <= 12.6; t += 0.5) bag.write("/odom", ros::Time(t), odom_msg(t, t));
    for (double t : {10.0, second, 12.0}) bag.write("/scan", ros::Time(t), scan_msg(t));
    bag.close();
  };
  // Another bag put in its place.
  write(11.0);
  auto stream = open_log(p);
  small_bag(dir + "/other.bag", [](rosbag::Bag& b) {
    b.write("/scan", ros::Time(12.5), scan_msg(12.5));
  });
  std::filesystem::rename(dir + "/other.bag", p);
  expect_input_error([&] { drain(*stream); }, {p, "changed while it was read"});

  // The same bag but for one scan's stamp, of the same size and with the
  // same modification time: found at that scan, after the steps before it.
  write(11.0);
  const auto size = std::filesystem::file_size(p);
  const auto modified = std::filesystem::last_write_time(p);
  stream = open_log(p);
  write(11.25);
  ASSERT_EQ(std::filesystem::file_size(p), size);
  std::filesystem::last_write_time(p, modified);
  LogStep step;
  ASSERT_TRUE(stream->next(step));
  expect_input_error([&] { stream->next(step); },
                     {p, "changed while it was read", "scan 1 on '/scan'"});
}

TEST(RosBag, Options) {
  Config cfg = Config::from_string(
      "[input]\nscan_topic = /base_scan\nodom_topic = tf\nodom_frame = /odom_combined\n"
      "base_frame = base_footprint\nlaser_pose = 0.1 -0.2 3.14\n", "test");
  BagOptions o;
  o.load(cfg, "input");
  EXPECT_NO_THROW(cfg.check_all_used());
  EXPECT_EQ(o.scan_topic, "/base_scan");
  EXPECT_EQ(o.odom_topic, "tf");
  EXPECT_EQ(o.odom_frame, "/odom_combined");
  EXPECT_EQ(o.base_frame, "base_footprint");
  EXPECT_TRUE(o.has_laser_pose);
  EXPECT_EQ(o.laser_pose.x, 0.1);
  EXPECT_EQ(o.laser_pose.y, -0.2);
  EXPECT_EQ(o.laser_pose.theta, 3.14);
  Config defaults;
  BagOptions d;
  d.load(defaults, "input");
  EXPECT_EQ(d.scan_topic, "auto");
  EXPECT_EQ(d.odom_topic, "auto");
  EXPECT_FALSE(d.has_laser_pose);
  for (const char* bad : {"laser_pose = 1 2", "laser_pose = 1 2 x", "laser_pose = 1 2 nan",
                          "scan_topic = a b", "odom_topic =", "base_frame = odom",
                          "odom_frame = /"}) {
    SCOPED_TRACE(bad);
    Config c = Config::from_string(std::string("[input]\n") + bad + "\n", "test");
    BagOptions b;
    EXPECT_THROW(b.load(c, "input"), ConfigError);
  }
}

}  // namespace
}  // namespace hmt::io

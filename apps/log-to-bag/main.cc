// log-to-bag: writes any log hmt-slam reads (CARMEN, rawlog) as a ROS 1
// bag, with odometry as nav_msgs/Odometry or as /tf transforms, so that a
// bag of known content can be mapped and compared with the log itself (see
// hmt/io/bag_writer.h for what the bag holds).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>
#include <vector>

#include "hmt/common/error.h"
#include "hmt/io/bag_writer.h"
#include "hmt/io/log_reader.h"
#include "hmt/version.h"

int main(int argc, char** argv) {
  CLI::App app{"Write a log (CARMEN, MRPT rawlog) as a ROS 1 bag"};
  app.set_version_flag("--version", hmt::version_string("log-to-bag"));
  std::string input, output, odometry = "topic";
  hmt::io::BagWriteOptions o;
  app.add_option("--input,-i", input, "log to convert")->required();
  app.add_option("--output,-o", output, "ROS bag to write")->required();
  app.add_option("--odometry", odometry,
                 "topic: nav_msgs/Odometry on --odom-topic; tf: /tf transforms")
      ->capture_default_str();
  app.add_option("--scan-topic", o.scan_topic, "sensor_msgs/LaserScan topic")->capture_default_str();
  app.add_option("--odom-topic", o.odom_topic, "nav_msgs/Odometry topic")->capture_default_str();
  app.add_option("--odom-frame", o.odom_frame, "odometry frame")->capture_default_str();
  app.add_option("--base-frame", o.base_frame, "robot frame")->capture_default_str();
  app.add_option("--laser-frame", o.laser_frame, "the scans' frame")->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : static_cast<int>(hmt::ExitCode::kUsage);
  }
  try {
    if (odometry == "topic")
      o.odometry = hmt::io::BagWriteOptions::Odometry::kTopic;
    else if (odometry == "tf")
      o.odometry = hmt::io::BagWriteOptions::Odometry::kTf;
    else
      throw hmt::UsageError("--odometry must be 'topic' or 'tf', not '" + odometry + "'");
    // A CARMEN log's own odometry poses, rather than the increments summed.
    std::vector<hmt::Pose2D> odom;
    const bool carmen = hmt::io::detect_log_format(input) == hmt::io::LogFormat::kCarmen;
    const hmt::Log log = carmen ? hmt::io::read_carmen(input, &odom) : hmt::io::read_log(input);
    hmt::io::write_bag(log, output, o, carmen ? &odom : nullptr);
    std::printf("wrote %zu scans to %s\n", log.steps.size(), output.c_str());
  } catch (const hmt::Error& e) {
    std::fprintf(stderr, "log-to-bag: error: %s\n", e.what());
    return static_cast<int>(e.code());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "log-to-bag: internal error: %s\n", e.what());
    return static_cast<int>(hmt::ExitCode::kInternal);
  }
  return 0;
}

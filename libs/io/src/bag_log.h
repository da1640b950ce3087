// The decoded content of a ROS bag -> the internal stream: which topics,
// odometry at each scan's stamp, the laser's mounting, the beams. The
// conventions are in hmt/io/rosbag.h; this part holds no ROS code, so it is
// tested on contents built in memory as well as on real bags.
#pragma once

#include <string>
#include <vector>

#include "bag_contents.h"
#include "bag_frames.h"
#include "hmt/common/sensor_data.h"
#include "hmt/io/rosbag.h"

namespace hmt::io::detail {

// The steps of a bag: every decision made on the first pass's contents,
// then each scan message of the second pass turned into its step.
class BagSteps {
 public:
  // Chooses the scan topic, the odometry and the robot frame, and which
  // scans become steps (with their odometry increments and mountings).
  // Throws hmt::InputError for every problem rosbag.h lists, the beams'
  // included, so that a bad bag fails before its first step. `source`
  // names the bag in messages.
  BagSteps(const std::string& source, const BagContents& contents, const BagOptions& options);

  const std::string& scan_topic() const { return scan_topic_; }
  // How many messages the scan topic has, and how many of them are steps.
  size_t messages() const { return scans_.size(); }
  size_t steps() const { return steps_; }

  // Message k of the scan topic, as the second pass decodes it: its step
  // into `out`, or false for a scan left out. Throws hmt::InputError when
  // the message is not the one the first pass read (the bag changed).
  bool step(size_t k, const BagScan& scan, LogStep& out) const;

  // Throws the hmt::InputError of a bag that changed between the two
  // passes, saying `how`.
  [[noreturn]] void changed(const std::string& how) const;

  // What the first pass decided for one scan message.
  struct Scan {
    BagScanInfo info;
    bool kept = false;  // it is a step
    bool has_odometry = false;
    Pose2D odometry_increment;
    Rigid mount;  // the laser in the robot frame
  };

 private:
  std::string source_;
  std::string scan_topic_;
  std::vector<Scan> scans_;
  size_t steps_ = 0;
};

}  // namespace hmt::io::detail

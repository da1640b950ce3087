// The decoded content of a ROS bag -> the internal stream: which topics,
// odometry at each scan's stamp, the laser's mounting, the beams. The
// conventions are in hmt/io/rosbag.h; this part holds no ROS code, so it is
// tested on contents built in memory as well as on real bags.
#pragma once

#include <string>

#include "bag_contents.h"
#include "hmt/common/sensor_data.h"
#include "hmt/io/rosbag.h"

namespace hmt::io::detail {

// `source` names the bag in messages and becomes the log's source.
hmt::Log bag_to_log(const std::string& source, const BagContents& contents,
                    const BagOptions& options);

}  // namespace hmt::io::detail

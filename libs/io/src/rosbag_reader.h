// The ROS bag reader as a stream, for open_log().
#pragma once

#include <memory>
#include <string>

#include "hmt/io/log_stream.h"
#include "hmt/io/rosbag.h"

namespace hmt::io::detail {

// Reads the bag in two passes through the plugin (rosbag_plugin_abi.h):
// the first, here, reads everything but the scans' readings and makes every
// decision (so a bad bag fails before its first step, with the errors
// rosbag.h lists); the second decodes the scan topic's messages one at a
// time as the steps are taken. A bag that changes between the passes is an
// error naming it.
std::unique_ptr<LogStream> open_bag(const std::string& path, const BagOptions& options);

}  // namespace hmt::io::detail

// Reading any supported log into the internal stream.
#pragma once

#include <string>

#include "hmt/common/sensor_data.h"
#include "hmt/io/carmen.h"
#include "hmt/io/rawlog.h"
#include "hmt/io/rosbag.h"

namespace hmt::io {

enum class LogFormat { kCarmen, kRawlog, kRosBag };

// Which reader read_log() picks for `path`, by content rather than by name:
// a ROS bag if the file starts with "#ROSBAG V" (a gzip-compressed bag is an
// error: rosbag reads only plain files), else CARMEN if the (decompressed) text starts, after blank lines, with a
// comment (#) or a CARMEN message name (FLASER, ODOM, PARAM, ROBOTLASER1,
// ...), else an MRPT rawlog. Throws hmt::InputError for a missing, non-regular
// or empty file.
LogFormat detect_log_format(const std::string& path);

// Reads a whole log (CARMEN or MRPT rawlog, gzip or not; ROS bag) into the
// internal stream; see carmen.h, rawlog.h and rosbag.h for the conventions
// (`bag` says which topics and frames of a bag to read). Throws
// hmt::InputError with a one-line message naming the file and the problem.
// It is open_log() drained (log_stream.h): to read a long log step by step,
// without holding it, use open_log().
hmt::Log read_log(const std::string& path, const BagOptions& bag = {});

}  // namespace hmt::io

// Reading any supported log into the internal stream.
#pragma once

#include <string>

#include "hmt/common/sensor_data.h"
#include "hmt/io/carmen.h"
#include "hmt/io/rawlog.h"

namespace hmt::io {

enum class LogFormat { kCarmen, kRawlog };

// Which reader read_log() picks for `path`, by content rather than by name:
// CARMEN if the (decompressed) text starts, after blank lines, with a
// comment (#) or a CARMEN message name (FLASER, ODOM, PARAM, ROBOTLASER1,
// ...), else an MRPT rawlog. Throws hmt::InputError for a missing, non-regular
// or empty file.
LogFormat detect_log_format(const std::string& path);

// Reads a whole log (CARMEN or MRPT rawlog, gzip or not) into the internal
// stream; see carmen.h and rawlog.h for the conventions. Throws
// hmt::InputError with a one-line message naming the file and the problem.
hmt::Log read_log(const std::string& path);

}  // namespace hmt::io

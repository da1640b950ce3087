// The rawlog reader with the knowledge of how it was chosen, so that
// open_log() can say "neither a CARMEN log nor an MRPT rawlog" for unknown
// content.
#pragma once

#include <memory>
#include <string>

#include "hmt/io/log_stream.h"

namespace hmt::io::detail {

// Reads the file entry by entry as the steps are taken (rawlog_collector.h
// says which scans wait for the odometry source). When the reader meets a
// class only MRPT reads, the MRPT plugin opens the file and reads it from
// its start, entry by entry too (mrpt_fallback.h): the steps already handed
// out are skipped, and the stream goes on with the plugin's.
std::unique_ptr<LogStream> open_rawlog(const std::string& path, bool chosen_by_content);

}  // namespace hmt::io::detail

// Reading a rawlog with MRPT itself, for files holding objects the native
// reader does not know (rawlog_objects.h). MRPT lives in a plugin loaded
// with dlopen() on first need, so that reading laser and odometry logs never
// maps MRPT's ~170 shared libraries into the process.
//
// The plugin is looked for, in order:
//  - at $HMT_IO_MRPT_PLUGIN when that is set (then nowhere else);
//  - next to the running executable (libhmt_io_mrpt.so);
//  - in the install tree (<exe dir>/../lib/hmt-slam/libhmt_io_mrpt.so);
//  - where the build put it (a path compiled in by CMake).
#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include "hmt/common/sensor_data.h"
#include "hmt/io/log_stream.h"

namespace hmt::io::detail {

// Opens the file for reading with MRPT, entry by entry as the steps are
// taken (mrpt_plugin_abi.h): the steps, and the InputError messages where
// the reader meets damage or finds the log unusable, are the ones the
// native reader gives. `needed_for` says what made MRPT necessary ("a
// CObservationImage (entry 3)"); it names the problem if the plugin cannot
// be loaded (or is of another build), which is an InputError too.
std::unique_ptr<LogStream> open_rawlog_with_mrpt(const std::string& path, bool chosen_by_content,
                                                 const std::string& needed_for);

// The same stream drained.
hmt::Log read_rawlog_with_mrpt(const std::string& path, bool chosen_by_content,
                               const std::string& needed_for);

// How many files have been opened with MRPT in this process.
size_t mrpt_fallback_reads();

}  // namespace hmt::io::detail

// What the MRPT plugin (libhmt_io_mrpt.so, built from
// libs/io/plugin/mrpt_rawlog_reader.cc) exports: one function, looked up with
// dlsym by mrpt_fallback.cc, that returns the plugin's functions for reading
// a rawlog step by step. Built with the rest of the project, so C++ types
// cross; the version in the symbol's name keeps an out-of-date plugin from
// being used. Exceptions do not cross: each function says how it ended.
#pragma once

#include <cstdint>
#include <string>

#include "hmt/common/sensor_data.h"
#include "plugin_status.h"

namespace hmt::io::detail {

// An open rawlog being read. Defined by the plugin; only pointers to it
// cross.
struct MrptRawlogCursor;

struct MrptRawlogPlugin {
  // Opens the rawlog at `path` (gzip or plain); see rawlog_reader.h for
  // `chosen_by_content`. Nothing is read yet.
  PluginStatus (*open)(const char* path, bool chosen_by_content, MrptRawlogCursor** cursor,
                       std::string* error);
  // The next step into *step and *got true; *got false at the clean end of
  // the log. Entries are read with MRPT's deserializers as the steps need
  // them, and collected by the RawlogCollector the native reader uses: the
  // steps, and the errors at the points they are found, are the native
  // reader's (rawlog_collector.h says which scans wait for the odometry
  // source).
  PluginStatus (*next)(MrptRawlogCursor* cursor, hmt::LogStep* step, bool* got,
                       std::string* error);
  // How far into the file (compressed bytes, if it is) reading has got.
  uint64_t (*file_offset)(const MrptRawlogCursor* cursor);
  // Closes the file and frees the cursor.
  void (*close)(MrptRawlogCursor* cursor);
};

using GetMrptRawlogPluginFn = const MrptRawlogPlugin* (*)();

constexpr const char* kMrptRawlogPluginSymbol = "hmt_io_mrpt_rawlog_plugin_v2";
constexpr const char* kMrptPluginFileName = "libhmt_io_mrpt.so";
constexpr const char* kMrptPluginEnv = "HMT_IO_MRPT_PLUGIN";

}  // namespace hmt::io::detail

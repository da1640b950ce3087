// The one function the MRPT plugin (libhmt_io_mrpt.so, built from
// libs/io/plugin) exports, looked up with dlsym by mrpt_fallback.cc. The
// plugin is built with the rest of the project, so C++ types may cross; the
// version in the symbol's name keeps an out-of-date plugin from being used.
#pragma once

#include <string>

#include "hmt/common/sensor_data.h"

namespace hmt::io::detail {

// What the plugin's reader returns: the log was read, the file is bad
// (`error` holds the hmt::InputError's one-line message), or something else
// failed (`error` says what).
enum class MrptReadStatus : int { kOk = 0, kInputError = 1, kFailure = 2 };

// Reads the rawlog at `path` with MRPT's own deserializers into *log; see
// rawlog_reader.h for `chosen_by_content`.
using MrptReadRawlogFn = MrptReadStatus (*)(const char* path,
                                            bool chosen_by_content,
                                            hmt::Log* log, std::string* error);

constexpr const char* kMrptReadRawlogSymbol = "hmt_io_mrpt_read_rawlog_v1";
constexpr const char* kMrptPluginFileName = "libhmt_io_mrpt.so";

}  // namespace hmt::io::detail

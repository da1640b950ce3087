// The one function the ROS bag plugin (libhmt_io_rosbag.so, built from
// libs/io/plugin/rosbag_reader.cc) exports, looked up with dlsym by
// rosbag_reader.cc. Built with the rest of the project, so C++ types cross;
// the version in the symbol's name keeps an out-of-date plugin from being
// used.
#pragma once

#include <string>

#include "bag_contents.h"

namespace hmt::io::detail {

// kInputError: the file is bad (`error` holds the hmt::InputError's one-line
// message); kFailure: something else failed (`error` says what).
enum class BagReadStatus : int { kOk = 0, kInputError = 1, kFailure = 2 };

using ReadBagContentsFn = BagReadStatus (*)(const char* path,
                                            BagContents* contents,
                                            std::string* error);

constexpr const char* kReadBagContentsSymbol = "hmt_io_rosbag_read_contents_v1";
constexpr const char* kRosbagPluginFileName = "libhmt_io_rosbag.so";
constexpr const char* kRosbagPluginEnv = "HMT_IO_ROSBAG_PLUGIN";

}  // namespace hmt::io::detail

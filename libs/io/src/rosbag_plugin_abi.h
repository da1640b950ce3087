// What the ROS bag plugin (libhmt_io_rosbag.so, built from
// libs/io/plugin/rosbag_reader.cc) exports: one function, looked up with
// dlsym by rosbag_reader.cc, that returns the plugin's functions for the two
// passes over a bag. Built with the rest of the project, so C++ types cross;
// the version in the symbol's name keeps an out-of-date plugin from being
// used. Exceptions do not cross: each function says how it ended.
#pragma once

#include <string>

#include "bag_contents.h"
#include "plugin_status.h"

namespace hmt::io::detail {

// The second pass over a bag: one topic's messages in the bag's order.
// Defined by the plugin; only pointers to it cross.
struct BagScanCursor;

struct RosbagPlugin {
  // The first pass: every topic, odometry message and transform, and the
  // LaserScan messages of every topic without their readings.
  PluginStatus (*read_contents)(const char* path, BagContents* contents, std::string* error);
  // The second pass over `topic`, a LaserScan topic: the messages are read
  // and decoded one at a time, as next_scan() asks for them.
  PluginStatus (*open_scans)(const char* path, const char* topic, BagScanCursor** cursor,
                             std::string* error);
  // The next message into *scan and *got true; *got false past the last.
  PluginStatus (*next_scan)(BagScanCursor* cursor, BagScan* scan, bool* got,
                            std::string* error);
  // Closes the bag and frees the cursor.
  void (*close_scans)(BagScanCursor* cursor);
};

using GetRosbagPluginFn = const RosbagPlugin* (*)();

constexpr const char* kRosbagPluginSymbol = "hmt_io_rosbag_plugin_v2";
constexpr const char* kRosbagPluginFileName = "libhmt_io_rosbag.so";
constexpr const char* kRosbagPluginEnv = "HMT_IO_ROSBAG_PLUGIN";

}  // namespace hmt::io::detail

#include "rosbag_reader.h"

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include "bag_contents.h"
#include "bag_log.h"
#include "hmt/common/error.h"
#include "hmt/common/files.h"
#include "plugin_loader.h"
#include "rosbag_plugin_abi.h"

#ifndef HMT_IO_ROSBAG_PLUGIN_PATH
#error "HMT_IO_ROSBAG_PLUGIN_PATH must name the plugin's build location"
#endif

namespace hmt::io {
namespace detail {
namespace {

const RosbagPlugin& load_plugin(const std::string& path) {
  std::string tried;
  const auto get = reinterpret_cast<GetRosbagPluginFn>(
      load_plugin_symbol(kRosbagPluginEnv, kRosbagPluginFileName, HMT_IO_ROSBAG_PLUGIN_PATH,
                         kRosbagPluginSymbol, tried));
  if (!get)
    throw InputError("'" + path + "' is a ROS bag, and the ROS bag reader plugin cannot be loaded (" +
                     tried + ")");
  return *get();
}

// A plugin function's outcome, as the exception it stands for.
void check(PluginStatus status, const std::string& path, const std::string& error) {
  throw_unless_ok(status, error, [&] { return "reading ROS bag '" + path + "'"; });
}

BagContents first_pass(const RosbagPlugin& plugin, const std::string& path) {
  BagContents contents;
  std::string error;
  check(plugin.read_contents(path.c_str(), &contents, &error), path, error);
  return contents;
}

// What tells the file read by the first pass from another one put in its
// place before the second: the odometry and transforms are not read again.
struct FileVersion {
  std::uintmax_t size;
  std::filesystem::file_time_type modified;
  bool operator==(const FileVersion& o) const {
    return size == o.size && modified == o.modified;
  }
};

FileVersion file_version(const std::string& path) {
  std::error_code ec;  // a file gone reads as size -1, unlike any file
  return {std::filesystem::file_size(path, ec), std::filesystem::last_write_time(path, ec)};
}

// The first pass is made on opening; the second as the steps are taken,
// holding one scan at a time.
class BagStream : public LogStream {
 public:
  BagStream(const std::string& path, const BagOptions& options)
      : LogStream(path),
        plugin_(load_plugin(path)),
        version_(file_version(path)),
        steps_(path, first_pass(plugin_, path), options),
        cursor_(nullptr, CloseScans{&plugin_}) {}

  bool next(LogStep& out) override {
    if (ended_) return false;
    if (!cursor_) open_second_pass();
    BagScan scan;
    std::string error;
    for (;;) {
      bool got = false;
      check(plugin_.next_scan(cursor_.get(), &scan, &got, &error), source(), error);
      if (!got) break;
      if (steps_.step(read_++, scan, out)) return true;
    }
    if (read_ != steps_.messages())
      steps_.changed(std::to_string(steps_.messages()) + " scans on '" + steps_.scan_topic() +
                     "' at first, " + std::to_string(read_) + " then");
    cursor_.reset();
    ended_ = true;
    return false;
  }

  // The share of the scan topic's messages read by the second pass.
  double fraction_read() const override {
    if (ended_) return 1.0;
    return static_cast<double>(read_) / static_cast<double>(steps_.messages());
  }
  std::optional<size_t> total_steps() const override { return steps_.steps(); }

 private:
  struct CloseScans {
    const RosbagPlugin* plugin;
    void operator()(BagScanCursor* c) const { plugin->close_scans(c); }
  };

  void open_second_pass() {
    if (!(file_version(source()) == version_))
      steps_.changed("its size or modification time is not what it was at first");
    BagScanCursor* cursor = nullptr;
    std::string error;
    check(plugin_.open_scans(source().c_str(), steps_.scan_topic().c_str(), &cursor, &error),
          source(), error);
    cursor_.reset(cursor);
  }

  const RosbagPlugin& plugin_;
  const FileVersion version_;
  const BagSteps steps_;
  std::unique_ptr<BagScanCursor, CloseScans> cursor_;
  size_t read_ = 0;  // scan messages read by the second pass
  bool ended_ = false;
};

}  // namespace

std::unique_ptr<LogStream> open_bag(const std::string& path, const BagOptions& options) {
  require_readable_file(path, "input log");
  return std::make_unique<BagStream>(path, options);
}

}  // namespace detail

hmt::Log read_bag(const std::string& path, const BagOptions& options) {
  return drain(*detail::open_bag(path, options));
}

}  // namespace hmt::io

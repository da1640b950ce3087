#include <stdexcept>

#include "bag_contents.h"
#include "bag_log.h"
#include "hmt/common/error.h"
#include "hmt/common/files.h"
#include "hmt/io/rosbag.h"
#include "plugin_loader.h"
#include "rosbag_plugin_abi.h"

#ifndef HMT_IO_ROSBAG_PLUGIN_PATH
#error "HMT_IO_ROSBAG_PLUGIN_PATH must name the plugin's build location"
#endif

namespace hmt::io {

hmt::Log read_bag(const std::string& path, const BagOptions& options) {
  require_readable_file(path, "input log");
  std::string tried;
  const auto read = reinterpret_cast<detail::ReadBagContentsFn>(detail::load_plugin_symbol(
      detail::kRosbagPluginEnv, detail::kRosbagPluginFileName, HMT_IO_ROSBAG_PLUGIN_PATH,
      detail::kReadBagContentsSymbol, tried));
  if (!read)
    throw InputError("'" + path + "' is a ROS bag, and the ROS bag reader plugin cannot be loaded (" +
                     tried + ")");
  detail::BagContents contents;
  std::string error;
  switch (read(path.c_str(), &contents, &error)) {
    case detail::BagReadStatus::kOk:
      return detail::bag_to_log(path, contents, options);
    case detail::BagReadStatus::kInputError:
      throw InputError(error);
    case detail::BagReadStatus::kFailure:
      break;
  }
  throw std::runtime_error("reading ROS bag '" + path + "': " + error);
}

}  // namespace hmt::io

#include "mrpt_fallback.h"

#include <atomic>
#include <stdexcept>

#include "hmt/common/error.h"
#include "mrpt_plugin_abi.h"
#include "plugin_loader.h"

#ifndef HMT_IO_MRPT_PLUGIN_PATH
#error "HMT_IO_MRPT_PLUGIN_PATH must name the plugin's build location"
#endif

namespace hmt::io::detail {
namespace {

std::atomic<size_t> g_fallback_reads{0};

// The plugin's reader, or nullptr with `tried` saying why not.
MrptReadRawlogFn load_reader(std::string& tried) {
  return reinterpret_cast<MrptReadRawlogFn>(
      load_plugin_symbol("HMT_IO_MRPT_PLUGIN", kMrptPluginFileName,
                         HMT_IO_MRPT_PLUGIN_PATH, kMrptReadRawlogSymbol, tried));
}

}  // namespace

hmt::Log read_rawlog_with_mrpt(const std::string& path, bool chosen_by_content,
                               const std::string& needed_for) {
  std::string tried;
  const MrptReadRawlogFn read = load_reader(tried);
  if (!read)
    throw InputError("rawlog '" + path + "' holds " + needed_for +
                     ", which only MRPT can read, and the MRPT reader plugin "
                     "cannot be loaded (" + tried + ")");
  ++g_fallback_reads;
  hmt::Log log;
  std::string error;
  switch (read(path.c_str(), chosen_by_content, &log, &error)) {
    case MrptReadStatus::kOk:
      return log;
    case MrptReadStatus::kInputError:
      throw InputError(error);
    case MrptReadStatus::kFailure:
      break;
  }
  throw std::runtime_error("reading rawlog '" + path + "' with MRPT: " + error);
}

size_t mrpt_fallback_reads() { return g_fallback_reads; }

}  // namespace hmt::io::detail

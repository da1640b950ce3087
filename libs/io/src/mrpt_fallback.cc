#include "mrpt_fallback.h"

#include <dlfcn.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <system_error>
#include <vector>

#include "hmt/common/error.h"
#include "mrpt_plugin_abi.h"

#ifndef HMT_IO_MRPT_PLUGIN_PATH
#error "HMT_IO_MRPT_PLUGIN_PATH must name the plugin's build location"
#endif

namespace hmt::io::detail {
namespace {

std::atomic<size_t> g_fallback_reads{0};

std::vector<std::string> plugin_candidates() {
  if (const char* env = std::getenv("HMT_IO_MRPT_PLUGIN"); env && *env)
    return {env};
  std::vector<std::string> out;
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) out.push_back((exe.parent_path() / kMrptPluginFileName).string());
  out.push_back(HMT_IO_MRPT_PLUGIN_PATH);
  return out;
}

// The plugin's reader, or nullptr with `tried` saying why not. The handle
// is never closed: MRPT registers its classes in static tables on load.
MrptReadRawlogFn load_reader(std::string& tried) {
  for (const std::string& path : plugin_candidates()) {
    if (!tried.empty()) tried += "; ";
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char* err = dlerror();
      tried += err ? err : path + ": cannot be loaded";
      continue;
    }
    if (void* fn = dlsym(handle, kMrptReadRawlogSymbol))
      return reinterpret_cast<MrptReadRawlogFn>(fn);
    tried += path + ": no " + kMrptReadRawlogSymbol + " (another build?)";
  }
  return nullptr;
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

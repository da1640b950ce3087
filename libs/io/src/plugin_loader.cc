#include "plugin_loader.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <system_error>
#include <vector>

#ifndef HMT_PLUGIN_RELATIVE_DIR
#error "HMT_PLUGIN_RELATIVE_DIR must name the installed plugins' folder relative to bin/"
#endif

namespace hmt::io::detail {
namespace {

std::vector<std::string> candidates(const char* env_var, const char* file_name,
                                    const char* build_path) {
  if (const char* env = std::getenv(env_var); env && *env) return {env};
  std::vector<std::string> out;
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    out.push_back((exe.parent_path() / file_name).string());
    out.push_back(
        (exe.parent_path() / HMT_PLUGIN_RELATIVE_DIR / file_name).lexically_normal().string());
  }
  out.push_back(build_path);
  return out;
}

}  // namespace

void* load_plugin_symbol(const char* env_var, const char* file_name,
                         const char* build_path, const char* symbol,
                         std::string& tried) {
  for (const std::string& path : candidates(env_var, file_name, build_path)) {
    if (!tried.empty()) tried += "; ";
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char* err = dlerror();
      tried += err ? err : path + ": cannot be loaded";
      continue;
    }
    if (void* fn = dlsym(handle, symbol)) return fn;
    tried += path + ": no " + symbol + " (another build?)";
  }
  return nullptr;
}

}  // namespace hmt::io::detail

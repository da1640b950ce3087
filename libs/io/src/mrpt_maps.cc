#include "hmt/io/mrpt_maps.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include "hmt/common/error.h"
#include "mrpt_maps_plugin_abi.h"
#include "plugin_loader.h"

#ifndef HMT_IO_MRPT_MAPS_PLUGIN_PATH
#error "HMT_IO_MRPT_MAPS_PLUGIN_PATH must name the plugin's build location"
#endif

namespace hmt::io {
namespace {

void* load(const char* symbol, const std::string& path) {
  std::string tried;
  void* fn = detail::load_plugin_symbol("HMT_IO_MRPT_MAPS_PLUGIN", detail::kMrptMapsPluginFileName,
                                        HMT_IO_MRPT_MAPS_PLUGIN_PATH, symbol, tried);
  if (!fn)
    throw OutputError("cannot write '" + path + "': the MRPT map writer plugin cannot be loaded (" +
                      tried + ")");
  return fn;
}

// MRPT writes the file under a temporary name beside `path`, which replaces
// `path` only once complete: a failure leaves an earlier file untouched.
template <typename Write>
void write_atomically(const std::string& path, Write write) {
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  std::string error;
  if (!write(tmp.c_str(), &error)) {
    std::remove(tmp.c_str());
    throw OutputError("cannot write '" + path + "': " + error);
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw OutputError("cannot move output into place at '" + path + "': " + ec.message());
  }
}

}  // namespace

void write_mrpt_gridmap(const MrptGridMap& grid, const std::string& path) {
  if (grid.size_x <= 0 || grid.size_y <= 0)
    throw std::invalid_argument("MRPT grid map '" + path + "': no cells (" +
                                std::to_string(grid.size_x) + " x " +
                                std::to_string(grid.size_y) + ")");
  if (!(grid.resolution > 0.0) || !std::isfinite(grid.resolution))
    throw std::invalid_argument("MRPT grid map '" + path + "': resolution " +
                                std::to_string(grid.resolution) + " is not positive");
  if (!grid.occupancy)
    throw std::invalid_argument("MRPT grid map '" + path + "': no occupancy function");
  const auto fn = reinterpret_cast<detail::MrptWriteGridmapFn>(
      load(detail::kMrptWriteGridmapSymbol, path));
  write_atomically(path, [&](const char* tmp, std::string* error) { return fn(&grid, tmp, error); });
}

void write_mrpt_simplemap(const std::vector<MapKeyframe>& keyframes, const std::string& path) {
  for (size_t i = 0; i < keyframes.size(); ++i) {
    if (keyframes[i].scan.ranges.empty())
      throw std::invalid_argument("MRPT simple map '" + path + "': keyframe " +
                                  std::to_string(i) + " has a scan without beams");
    if (!keyframes[i].pose.cov.allFinite())
      throw std::invalid_argument("MRPT simple map '" + path + "': keyframe " +
                                  std::to_string(i) + " has a covariance that is not finite");
  }
  const auto fn = reinterpret_cast<detail::MrptWriteSimplemapFn>(
      load(detail::kMrptWriteSimplemapSymbol, path));
  write_atomically(path,
                   [&](const char* tmp, std::string* error) { return fn(&keyframes, tmp, error); });
}

}  // namespace hmt::io

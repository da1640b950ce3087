// The two functions the MRPT map-writer plugin (libhmt_io_mrpt_maps.so,
// built from libs/io/plugin/mrpt_maps_writer.cc) exports, looked up with
// dlsym by mrpt_maps.cc. Built with the project, so C++ types cross; the
// version in the symbols' names keeps an out-of-date plugin from being used.
#pragma once

#include <string>
#include <vector>

#include "hmt/io/mrpt_maps.h"

namespace hmt::io::detail {

// true: written; false: `error` says why (nothing is left at `path`).
using MrptWriteGridmapFn = bool (*)(const MrptGridMap* grid, const char* path,
                                    std::string* error);
using MrptWriteSimplemapFn = bool (*)(const std::vector<MapKeyframe>* keyframes,
                                      const char* path, std::string* error);

constexpr const char* kMrptWriteGridmapSymbol = "hmt_io_mrpt_write_gridmap_v1";
constexpr const char* kMrptWriteSimplemapSymbol = "hmt_io_mrpt_write_simplemap_v1";
constexpr const char* kMrptMapsPluginFileName = "libhmt_io_mrpt_maps.so";

}  // namespace hmt::io::detail

// Loading one of hmt_io's optional readers (MRPT, ROS bags), each a plugin
// that maps its heavy libraries into the process only when a log needs it.
// A plugin is looked for, in order:
//  - at $<env_var> when that is set (then nowhere else);
//  - next to the running executable (<file_name>);
//  - in the install tree, <exe dir>/../lib/hmt-slam/<file_name> (the folder
//    `cmake --install` puts plugins in, relative to the programs' bin/, so
//    an installed prefix can be moved: HMT_PLUGIN_RELATIVE_DIR);
//  - where the build put it (`build_path`, compiled in by CMake).
#pragma once

#include <string>

namespace hmt::io::detail {

// The address of `symbol` in the first candidate that loads and has it, or
// nullptr with `tried` saying what went wrong with each. Handles are never
// closed: plugins register static state on load.
void* load_plugin_symbol(const char* env_var, const char* file_name,
                         const char* build_path, const char* symbol,
                         std::string& tried);

}  // namespace hmt::io::detail

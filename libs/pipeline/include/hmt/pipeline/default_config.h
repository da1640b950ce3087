// The built-in configuration and how the command line layers on it.
//
// The defaults are config/default.ini itself, compiled into the program at
// build time (cmake/embed_text.cmake), so that the file stays the single,
// documented source of every default: `hmt-slam run --input LOG` needs no
// configuration file, and `hmt-slam config --dump` prints the text.
#pragma once

#include <string>
#include <vector>

#include "hmt/common/config.h"

namespace hmt::pipeline {

// The text of config/default.ini, byte for byte.
const std::string& default_config_text();

// The folder the defaults' relative paths ([input] log) are taken from: the
// source tree's config/, where default.ini lives.
std::string default_config_dir();

// The built-in defaults, then each of `files` in order, then each of `sets`
// ("SECTION.key=value"), each layer's keys replacing the ones below. A --set
// path is taken from the last file's folder (from the current folder when
// there is none). Throws ConfigError for a file that cannot be read or
// parsed; unknown keys are found when the options are loaded
// (load_job_options), naming the layer that gave them.
Config layered_config(const std::vector<std::string>& files,
                      const std::vector<std::string>& sets);

}  // namespace hmt::pipeline

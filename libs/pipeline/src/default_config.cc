#include "hmt/pipeline/default_config.h"

#include <filesystem>

#ifndef HMT_DEFAULT_CONFIG_DIR
#error "HMT_DEFAULT_CONFIG_DIR must name the folder of config/default.ini"
#endif

namespace hmt::pipeline {
namespace embedded {
// cmake/embed_text.cmake's output (default_config_text.cc in the build).
extern const char kDefaultIni[];
}  // namespace embedded

const std::string& default_config_text() {
  static const std::string text(embedded::kDefaultIni);
  return text;
}

std::string default_config_dir() { return HMT_DEFAULT_CONFIG_DIR; }

Config layered_config(const std::vector<std::string>& files,
                      const std::vector<std::string>& sets) {
  Config cfg = Config::from_string(default_config_text(), "<built-in config/default.ini>",
                                   default_config_dir());
  std::string set_dir;
  for (const std::string& file : files) {
    cfg.overlay(Config::from_file(file));
    set_dir = std::filesystem::path(file).parent_path().string();
  }
  for (const std::string& s : sets) cfg.apply_override(s, set_dir);
  return cfg;
}

}  // namespace hmt::pipeline

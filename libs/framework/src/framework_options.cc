#include "hmt/framework/framework_options.h"

namespace hmt::framework {

void FrameworkOptions::load(Config& cfg, const std::string& s) {
  const std::string m = cfg.get_string(s, "mode", "deterministic");
  inbox_capacity = cfg.get_int(s, "inbox_capacity", inbox_capacity);
  require(m == "deterministic" || m == "live", s, "mode", "'deterministic' or 'live'");
  mode = m == "live" ? Mode::kLive : Mode::kDeterministic;
  require(inbox_capacity >= 1 && inbox_capacity <= 100000, s, "inbox_capacity",
          "in [1, 100000]");
}

}  // namespace hmt::framework

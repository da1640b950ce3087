#include "hmt/framework/framework_options.h"

namespace hmt::framework {

void FrameworkOptions::load(Config& cfg, const std::string& s) {
  const std::string m = cfg.get_string(s, "mode", "deterministic");
  inbox_capacity = cfg.get_int(s, "inbox_capacity", inbox_capacity);
  live_speed = cfg.get_double(s, "live_speed", live_speed);
  rtl_probe_hz = cfg.get_double(s, "rtl_probe_hz", rtl_probe_hz);
  require(m == "deterministic" || m == "live", s, "mode", "'deterministic' or 'live'");
  mode = m == "live" ? Mode::kLive : Mode::kDeterministic;
  require(inbox_capacity >= 1 && inbox_capacity <= 100000, s, "inbox_capacity",
          "in [1, 100000]");
  require(live_speed >= 0 && live_speed <= 1e6, s, "live_speed", "in [0, 1e6]");
  require(rtl_probe_hz >= 0 && rtl_probe_hz <= 10000, s, "rtl_probe_hz", "in [0, 10000]");
}

}  // namespace hmt::framework

// The INI configuration parser and --set overrides on arbitrary text.
//
// The input is an INI text, then optionally a line "--set" followed by one
// override per line (SECTION.key=value), as hmt-slam applies them. Every key
// is then read as each type, and the effective configuration written to an
// output folder must parse back to the same values: it is how a run says
// what it used.
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_support.h"
#include "hmt/common/config.h"
#include "hmt/common/error.h"

namespace {

constexpr std::string_view kSetMarker = "\n--set\n";

void read_every_key(hmt::Config& cfg) {
  for (const auto& [section, key] : cfg.keys()) {
    try { cfg.get_double(section, key, 0.0); } catch (const hmt::ConfigError&) {}
    try { cfg.get_int(section, key, 0); } catch (const hmt::ConfigError&) {}
    try { cfg.get_bool(section, key, false); } catch (const hmt::ConfigError&) {}
    cfg.get_string(section, key, "");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  const size_t marker = input.find(kSetMarker);
  const std::string ini = input.substr(0, marker);
  std::vector<std::string> sets;
  if (marker != std::string::npos) {
    std::string_view rest(input);
    rest.remove_prefix(marker + kSetMarker.size());
    while (!rest.empty()) {
      const size_t nl = rest.find('\n');
      sets.emplace_back(rest.substr(0, nl));
      rest.remove_prefix(nl == std::string_view::npos ? rest.size() : nl + 1);
    }
  }
  hmt::Config cfg;
  try {
    cfg = hmt::Config::from_string(ini, "fuzz.ini");
    for (const std::string& s : sets) cfg.apply_override(s);
  } catch (const hmt::ConfigError&) {
    return 0;
  }
  // A key never read is an error naming it.
  if (!cfg.keys().empty()) {
    bool refused = false;
    try {
      cfg.check_all_used();
    } catch (const hmt::ConfigError&) {
      refused = true;
    }
    hmt::fuzz::check(refused, "check_all_used() accepted keys no one read");
  }
  read_every_key(cfg);
  cfg.check_all_used();  // every key read now: must not throw

  // The effective configuration reads back as the same values.
  const std::string effective = cfg.effective_ini();
  hmt::Config again;
  try {
    again = hmt::Config::from_string(effective, "config_effective.ini");
  } catch (const hmt::ConfigError& e) {
    hmt::fuzz::finding(std::string("the effective configuration does not parse: ") + e.what());
  }
  hmt::fuzz::check(again.keys() == cfg.keys(), "the effective configuration has other keys");
  for (const auto& [section, key] : cfg.keys())
    hmt::fuzz::check(again.get_string(section, key, "") == cfg.get_string(section, key, ""),
                     "[" + section + "] " + key + " reads back differently");
  return 0;
}

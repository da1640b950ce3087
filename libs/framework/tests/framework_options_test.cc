#include "hmt/framework/framework_options.h"

#include <gtest/gtest.h>

#include "hmt/common/error.h"

namespace hmt::framework {
namespace {

FrameworkOptions load(const std::string& text) {
  Config cfg = Config::from_string(text, "test");
  FrameworkOptions o;
  o.load(cfg);
  cfg.check_all_used();
  return o;
}

TEST(FrameworkOptions, ReadsEveryKey) {
  const FrameworkOptions o = load(
      "[framework]\nmode = live\ninbox_capacity = 8\nlive_speed = 2.5\nrtl_probe_hz = 50\n");
  EXPECT_EQ(o.mode, Mode::kLive);
  EXPECT_EQ(o.inbox_capacity, 8);
  EXPECT_EQ(o.live_speed, 2.5);
  EXPECT_EQ(o.rtl_probe_hz, 50.0);
  EXPECT_EQ(load("").mode, Mode::kDeterministic);
}

TEST(FrameworkOptions, BadValuesAreConfigErrorsNamingTheKey) {
  for (const char* bad : {"mode = fast", "inbox_capacity = 0", "live_speed = -1",
                          "rtl_probe_hz = -5", "inbox_capacity = many"}) {
    try {
      load(std::string("[framework]\n") + bad + "\n");
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const ConfigError& e) {
      const std::string key = std::string(bad).substr(0, std::string(bad).find(' '));
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace hmt::framework

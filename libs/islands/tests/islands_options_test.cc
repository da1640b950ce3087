#include "hmt/islands/islands_options.h"

#include <gtest/gtest.h>

#include <string>

#include "hmt/common/error.h"

namespace hmt::islands {
namespace {

// config/default.ini is where the defaults are documented: the code's
// defaults must be the same, key by key.
TEST(IslandsOptions, DefaultsAreThoseOfDefaultIni) {
  Config cfg = Config::from_file(std::string(HMT_SOURCE_DIR) + "/config/default.ini");
  IslandsOptions file;
  file.load(cfg);
  Config none = Config::from_string("", "test");
  IslandsOptions code;
  code.load(none);
  EXPECT_EQ(file.wall_probability, code.wall_probability);
  EXPECT_EQ(file.rays, code.rays);
  EXPECT_EQ(file.field_of_view, code.field_of_view);
  EXPECT_EQ(file.headings, code.headings);
  EXPECT_EQ(file.max_range, code.max_range);
  EXPECT_EQ(file.decay, code.decay);
  EXPECT_EQ(file.cutoff, code.cutoff);
  EXPECT_EQ(file.rate, code.rate);
  EXPECT_EQ(file.epsilon, code.epsilon);
  EXPECT_EQ(file.stride, code.stride);
  EXPECT_EQ(file.normal_radius, code.normal_radius);
  EXPECT_EQ(file.reference_window, code.reference_window);
  EXPECT_EQ(file.threshold, code.threshold);
  EXPECT_EQ(file.min_distance, code.min_distance);
  EXPECT_EQ(file.threads, code.threads);
  EXPECT_NE(none.effective_ini().find("[islands]"), std::string::npos);
  EXPECT_NE(none.effective_ini().find("decay = 0.25"), std::string::npos);
}

TEST(IslandsOptions, ReadsItsKeys) {
  Config cfg = Config::from_string(
      "[islands]\nrays = 360\nfield_of_view = 270\ndecay = 0.5\ncutoff = 0.8\nrate = 2\n"
      "epsilon = 0\nstride = 3\nthreshold = 0.7\nmin_distance = 5\n",
      "test");
  IslandsOptions o;
  o.load(cfg);
  EXPECT_NO_THROW(cfg.check_all_used());
  EXPECT_EQ(o.rays, 360);
  EXPECT_EQ(o.field_of_view, 270.0);
  EXPECT_EQ(o.decay, 0.5);
  EXPECT_EQ(o.cutoff, 0.8);
  EXPECT_EQ(o.rate, 2.0);
  EXPECT_EQ(o.epsilon, 0.0);
  EXPECT_EQ(o.stride, 3);
  EXPECT_EQ(o.threshold, 0.7);
  EXPECT_EQ(o.min_distance, 5.0);
}

TEST(IslandsOptions, InvalidValuesAreConfigurationErrors) {
  for (const std::string bad :
       {"rays = 2", "field_of_view = 0", "field_of_view = 400", "headings = 0", "max_range = 0",
        "decay = -1", "cutoff = 0", "rate = 0", "epsilon = -0.1", "stride = 0",
        "normal_radius = 0", "reference_window = 0.5", "threshold = 1.5", "min_distance = -1",
        "threads = -1", "rays = many", "wall_probability = 1"}) {
    SCOPED_TRACE(bad);
    Config cfg = Config::from_string("[islands]\n" + bad + "\n", "test");
    IslandsOptions o;
    EXPECT_THROW(o.load(cfg), ConfigError);
  }
}

}  // namespace
}  // namespace hmt::islands

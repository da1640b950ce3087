#include "hmt/area/area_options.h"

#include <gtest/gtest.h>

#include "hmt/common/config.h"
#include "hmt/common/error.h"

namespace hmt::area {
namespace {

TEST(area_Options, ReadsEveryKeyAndLeavesNoneUnused) {
  Config cfg = Config::from_string(
      "[area]\n"
      "delta = 0.15\nuse_probabilistic = true\nbeta = 0.01\n"
      "range_std = 0.02\nbearing_std = 0.001\ngate = 5.99\n"
      "descriptor_threshold = 0.4\ntau = 0.8\nmin_cluster_size = 3\n"
      "split_method = sweep\nmin_sso = 0.01\nwindow_size = 150\n"
      "index_cell_size = 2.5\nthreads = 3\n",
      "area.ini");
  AreaOptions o;
  o.load(cfg);
  EXPECT_NO_THROW(cfg.check_all_used());
  EXPECT_DOUBLE_EQ(o.sso.delta, 0.15);
  EXPECT_TRUE(o.sso.use_probabilistic);
  EXPECT_DOUBLE_EQ(o.sso.beta, 0.01);
  EXPECT_DOUBLE_EQ(o.sso.range_std, 0.02);
  EXPECT_DOUBLE_EQ(o.sso.bearing_std, 0.001);
  EXPECT_DOUBLE_EQ(o.sso.gate, 5.99);
  EXPECT_DOUBLE_EQ(o.sso.descriptor_threshold, 0.4);
  EXPECT_DOUBLE_EQ(o.partition.tau, 0.8);
  EXPECT_EQ(o.partition.min_cluster_size, 3);
  EXPECT_EQ(o.partition.split_method, SplitMethod::kSweep);
  EXPECT_DOUBLE_EQ(o.min_sso, 0.01);
  EXPECT_EQ(o.window_size, 150);
  EXPECT_DOUBLE_EQ(o.index_cell_size, 2.5);
  EXPECT_EQ(o.threads, 3);
}

TEST(area_Options, DefaultsAreRecordedInTheEffectiveConfig) {
  Config cfg = Config::from_string("", "empty.ini");
  AreaOptions o;
  o.load(cfg, "aam");
  const std::string ini = cfg.effective_ini();
  for (const char* key :
       {"delta", "use_probabilistic", "beta", "range_std", "bearing_std",
        "gate", "descriptor_threshold", "tau", "min_cluster_size",
        "split_method", "min_sso", "window_size", "index_cell_size", "threads"})
    EXPECT_NE(ini.find(std::string(key) + " = "), std::string::npos) << key;
  EXPECT_NE(ini.find("[aam]"), std::string::npos);
  EXPECT_NE(ini.find("split_method = mean"), std::string::npos);
  // tau's default is derived from the sensor once the log is read.
  EXPECT_TRUE(o.partition.tau_from_sensor);
  EXPECT_NE(ini.find("tau = auto"), std::string::npos);
}

TEST(area_Options, OutOfRangeValuesAreConfigErrors) {
  const char* bad[] = {"delta = 0",
                       "delta = -1",
                       "beta = -0.1",
                       "range_std = -1",
                       "bearing_std = -1",
                       "gate = 0",
                       "descriptor_threshold = -1",
                       "tau = 2.5",
                       "tau = -0.1",
                       "min_cluster_size = 0",
                       "split_method = median",
                       "min_sso = 1",
                       "min_sso = -0.5",
                       "window_size = 1",
                       "index_cell_size = 0",
                       "threads = -1",
                       "threads = 1025",
                       "threads = two"};
  for (const char* line : bad) {
    Config cfg =
        Config::from_string(std::string("[area]\n") + line + "\n", "t");
    AreaOptions o;
    EXPECT_THROW(o.load(cfg), ConfigError) << line;
  }
}

TEST(area_Options, SplitMethodNamesRoundTrip) {
  for (SplitMethod m :
       {SplitMethod::kMean, SplitMethod::kSign, SplitMethod::kSweep})
    EXPECT_EQ(parse_split_method(to_string(m), "s", "k"), m);
}

}  // namespace
}  // namespace hmt::area

#include "hmt/global_map/global_map_options.h"

#include <gtest/gtest.h>

#include <string>

#include "hmt/common/error.h"

namespace hmt::global_map {
namespace {

TEST(GlobalMapOptions, DefaultsAreTheKeyframeGraph) {
  Config cfg = Config::from_string("", "test");
  GlobalMapOptions opt;
  opt.load(cfg);
  EXPECT_EQ(opt.method, GlobalMapMethod::kKeyframes);
  EXPECT_EQ(opt.graph.kernel, RobustKernel::kDcs);
  EXPECT_NE(cfg.effective_ini().find("[global_map]"), std::string::npos);
  EXPECT_NE(cfg.effective_ini().find("method = keyframes"), std::string::npos);
}

TEST(GlobalMapOptions, ReadsItsKeys) {
  Config cfg = Config::from_string(
      "[global_map]\nmethod = areas\nrobust_kernel = huber\nrobust_chi2 = 4\n"
      "match = false\nmatch_min_ratio = 0.4\nrounds = 2\nin_area_std_xy = 0.05\n"
      "match_reuse = false\nmatch_own_area = false\n",
      "test");
  GlobalMapOptions opt;
  opt.load(cfg);
  EXPECT_NO_THROW(cfg.check_all_used());
  EXPECT_EQ(opt.method, GlobalMapMethod::kAreas);
  EXPECT_EQ(opt.graph.kernel, RobustKernel::kHuber);
  EXPECT_EQ(opt.graph.robust_chi2, 4.0);
  EXPECT_FALSE(opt.graph.match);
  EXPECT_FALSE(opt.graph.match_reuse);
  EXPECT_FALSE(opt.graph.match_own_area);
  EXPECT_EQ(opt.graph.match_min_ratio, 0.4);
  EXPECT_EQ(opt.graph.rounds, 2);
  EXPECT_EQ(opt.graph.in_area_std_xy, 0.05);
}

TEST(GlobalMapOptions, InvalidValuesAreConfigurationErrors) {
  for (const std::string bad :
       {"method = both", "robust_kernel = cauchy", "robust_chi2 = 0", "match_min_ratio = 1.5",
        "in_area_std_xy = 0", "step_std_theta = -1", "match_inflation = 0.5", "rounds = 0",
        "max_iterations = 0", "relative_tolerance = 1", "match_gate_xy = 0",
        "match_reuse = sometimes", "match_own_area = 2"}) {
    SCOPED_TRACE(bad);
    Config cfg = Config::from_string("[global_map]\n" + bad + "\n", "test");
    GlobalMapOptions opt;
    EXPECT_THROW(opt.load(cfg), ConfigError);
  }
}

}  // namespace
}  // namespace hmt::global_map

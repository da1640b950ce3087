#include <gtest/gtest.h>

#include <string>

#include "hmt/alignment/grid_alignment.h"
#include "hmt/common/error.h"

namespace hmt::alignment {
namespace {

TEST(AlignmentOptions, DefaultsLoadFromAnEmptyFile) {
  Config cfg = Config::from_string("", "test");
  AlignmentOptions opt;
  opt.load(cfg);
  const AlignmentOptions def;
  EXPECT_EQ(opt.min_points, def.min_points);
  EXPECT_EQ(opt.gate_chi2, def.gate_chi2);
  EXPECT_EQ(opt.covariance_inflation, def.covariance_inflation);
  // Every effective value is recorded under [alignment].
  EXPECT_NE(cfg.effective_ini().find("[alignment]"), std::string::npos);
  EXPECT_NE(cfg.effective_ini().find("gate_chi2"), std::string::npos);
}

TEST(AlignmentOptions, ReadsEveryKey) {
  const std::string text =
      "[alignment]\n"
      "occupied_probability = 0.7\n"
      "min_hits = 2\n"
      "min_points = 20\n"
      "icp_threshold_start = 2.0\n"
      "icp_threshold_angular = 0.1\n"
      "icp_threshold_decay = 0.6\n"
      "icp_threshold_end = 0.02\n"
      "icp_max_iterations = 50\n"
      "refine_iterations = 4\n"
      "match_distance = 0.2\n"
      "normal_radius = 0.3\n"
      "robust_scale = 0.04\n"
      "covariance_inflation = 3\n"
      "sigma_floor_xy = 0.003\n"
      "sigma_floor_theta = 0.002\n"
      "min_inlier_ratio = 0.4\n"
      "gate_chi2 = 11.3\n"
      "min_information_ratio = 0.05\n"
      "max_sigma_xy = 0.5\n"
      "max_sigma_theta = 0.1\n";
  Config cfg = Config::from_string(text, "test");
  AlignmentOptions opt;
  opt.load(cfg);
  EXPECT_NO_THROW(cfg.check_all_used());  // no key left unread
  EXPECT_EQ(opt.occupied_probability, 0.7);
  EXPECT_EQ(opt.min_hits, 2);
  EXPECT_EQ(opt.min_points, 20);
  EXPECT_EQ(opt.icp_threshold_start, 2.0);
  EXPECT_EQ(opt.icp_threshold_angular, 0.1);
  EXPECT_EQ(opt.icp_threshold_decay, 0.6);
  EXPECT_EQ(opt.icp_threshold_end, 0.02);
  EXPECT_EQ(opt.icp_max_iterations, 50);
  EXPECT_EQ(opt.refine_iterations, 4);
  EXPECT_EQ(opt.match_distance, 0.2);
  EXPECT_EQ(opt.normal_radius, 0.3);
  EXPECT_EQ(opt.robust_scale, 0.04);
  EXPECT_EQ(opt.covariance_inflation, 3.0);
  EXPECT_EQ(opt.sigma_floor_xy, 0.003);
  EXPECT_EQ(opt.sigma_floor_theta, 0.002);
  EXPECT_EQ(opt.min_inlier_ratio, 0.4);
  EXPECT_EQ(opt.gate_chi2, 11.3);
  EXPECT_EQ(opt.min_information_ratio, 0.05);
  EXPECT_EQ(opt.max_sigma_xy, 0.5);
  EXPECT_EQ(opt.max_sigma_theta, 0.1);
}

TEST(AlignmentOptions, AnotherSectionName) {
  Config cfg = Config::from_string("[tlca_align]\nmin_points = 7\n", "test");
  AlignmentOptions opt;
  opt.load(cfg, "tlca_align");
  EXPECT_EQ(opt.min_points, 7);
  EXPECT_NO_THROW(cfg.check_all_used());
}

TEST(AlignmentOptions, RejectsBadValues) {
  const char* bad[] = {
      "occupied_probability = 0.5",  "occupied_probability = 0.99",
      "min_hits = 0",                "min_points = 2",
      "icp_threshold_start = 0",     "icp_threshold_angular = -0.1",
      "icp_threshold_decay = 1",     "icp_threshold_decay = 0",
      "icp_threshold_end = 0",       "icp_threshold_end = 5",
      "icp_max_iterations = 0",      "refine_iterations = -1",
      "match_distance = 0",          "normal_radius = -1",
      "robust_scale = 0",            "covariance_inflation = 0.5",
      "sigma_floor_xy = 0",          "sigma_floor_theta = -0.001",
      "min_inlier_ratio = 1.5",      "min_inlier_ratio = -0.1",
      "gate_chi2 = 0",               "gate_chi2 = nan",
      "max_sigma_xy = 0.001",        "max_sigma_theta = 0.0005",
      "min_information_ratio = 1",   "min_information_ratio = -0.5",
      "match_distance = nan"};
  for (const char* line : bad) {
    SCOPED_TRACE(line);
    Config cfg = Config::from_string(std::string("[alignment]\n") + line + "\n", "test");
    AlignmentOptions opt;
    EXPECT_THROW(opt.load(cfg), ConfigError);
  }
  // Not a number at all: Config's own parse error.
  Config cfg = Config::from_string("[alignment]\nmin_points = many\n", "test");
  AlignmentOptions opt;
  EXPECT_THROW(opt.load(cfg), ConfigError);
}

}  // namespace
}  // namespace hmt::alignment

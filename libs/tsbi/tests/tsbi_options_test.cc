#include "hmt/tsbi/tsbi_options.h"

#include <gtest/gtest.h>

#include <string>

#include "hmt/common/error.h"

namespace hmt::tsbi {
namespace {

TEST(TsbiOptions, ReadsTheEvidenceKeys) {
  Config cfg = Config::from_string("[tsbi]\nevidence_cell = 0\nevidence_gain = 30\n", "test");
  TsbiOptions o;
  o.load(cfg);
  EXPECT_NO_THROW(cfg.check_all_used());
  EXPECT_EQ(o.evidence_cell, 0.0);
  EXPECT_EQ(o.evidence_gain, 30.0);
}

TEST(TsbiOptions, InvalidEvidenceAndFreeSpaceValuesAreErrorsNamingTheKey) {
  for (const auto& [bad, key] :
       {std::pair<std::string, std::string>{"evidence_cell = -0.25", "evidence_cell"},
        {"evidence_cell = 1000", "evidence_cell"},
        {"evidence_cell = wide", "evidence_cell"},
        {"evidence_gain = 0", "evidence_gain"},
        {"evidence_gain = -3.5", "evidence_gain"},
        {"evidence_gain = inf", "evidence_gain"},
        {"max_points_contradicted = -0.1", "max_points_contradicted"},
        {"max_points_contradicted = 1.5", "max_points_contradicted"},
        {"max_points_contradicted = some", "max_points_contradicted"},
        {"free_probability = 0", "free_probability"},
        {"free_probability = 0.5", "free_probability"},
        {"free_probability = nan", "free_probability"}}) {
    SCOPED_TRACE(bad);
    Config cfg = Config::from_string("[tsbi]\n" + bad + "\n", "test");
    TsbiOptions o;
    try {
      o.load(cfg);
      ADD_FAILURE() << "accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
}

TEST(TsbiOptions, ReadsTheFreeSpaceKeys) {
  Config cfg = Config::from_string(
      "[tsbi]\nmax_points_contradicted = 1\nfree_probability = 0.2\n", "test");
  TsbiOptions o;
  o.load(cfg);
  EXPECT_NO_THROW(cfg.check_all_used());
  EXPECT_EQ(o.max_points_contradicted, 1.0);
  EXPECT_EQ(o.free_probability, 0.2);
}

}  // namespace
}  // namespace hmt::tsbi

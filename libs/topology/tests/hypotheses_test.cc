#include "hmt/topology/hypotheses.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace hmt::topology {
namespace {

TopologicalHypothesis hyp(std::vector<PathEntry> path, double weight) {
  TopologicalHypothesis h;
  h.path = std::move(path);
  h.log_weight = std::log(weight);
  return h;
}

TEST(Hypotheses, PositionPmfSumsParticleWeightsPerArea) {
  // Fig. 4's situation after the robot entered its fifth area: some
  // particles say "new area 4", others "back in area 0" or "in area 1".
  // Weights 1, 2, 3, 4, 10 (unnormalised, total 20).
  const std::vector<PathEntry> base = {{0, 0}, {1, 50}, {2, 90}, {3, 130}};
  auto with = [&](AreaId last, double w) {
    auto p = base;
    p.push_back({last, 170});
    return hyp(p, w);
  };
  std::vector<TopologicalHypothesis> hs = {with(4, 1), with(0, 2), with(4, 3),
                                           with(1, 4), with(0, 10)};
  const auto pmf = position_pmf(hs);
  ASSERT_EQ(pmf.size(), 3u);
  EXPECT_NEAR(pmf.at(4), 4.0 / 20, 1e-15);
  EXPECT_NEAR(pmf.at(0), 12.0 / 20, 1e-15);
  EXPECT_NEAR(pmf.at(1), 4.0 / 20, 1e-15);
  double sum = 0;
  for (const auto& kv : pmf) sum += kv.second;
  EXPECT_NEAR(sum, 1.0, 1e-15);

  // Log weights far from zero (as after many steps) change nothing.
  for (auto& h : hs) h.log_weight -= 5000;
  const auto shifted = position_pmf(hs);
  EXPECT_NEAR(shifted.at(0), 0.6, 1e-12);
  // A particle of weight zero counts for nothing.
  hs[4].log_weight = -std::numeric_limits<double>::infinity();
  const auto pruned = position_pmf(hs);
  EXPECT_NEAR(pruned.at(0), 0.2, 1e-12);
  EXPECT_NEAR(pruned.at(4), 0.4, 1e-12);
}

TEST(Hypotheses, PathPmfGroupsIdenticalTopologies) {
  std::vector<TopologicalHypothesis> hs = {
      hyp({{0, 0}, {1, 10}, {2, 20}}, 1), hyp({{0, 0}, {1, 10}, {0, 20}}, 4),
      hyp({{0, 0}, {1, 12}, {2, 25}}, 2),  // same areas, other steps
      hyp({{0, 0}, {1, 10}, {3, 20}}, 2)};
  const auto pmf = path_pmf(hs);
  ASSERT_EQ(pmf.size(), 3u);
  EXPECT_EQ(pmf[0].areas, (std::vector<AreaId>{0, 1, 0}));
  EXPECT_NEAR(pmf[0].probability, 4.0 / 9, 1e-15);
  EXPECT_EQ(pmf[1].areas, (std::vector<AreaId>{0, 1, 2}));  // 1 + 2
  EXPECT_NEAR(pmf[1].probability, 3.0 / 9, 1e-15);
  EXPECT_EQ(pmf[2].areas, (std::vector<AreaId>{0, 1, 3}));
  EXPECT_NEAR(pmf[2].probability, 2.0 / 9, 1e-15);
}

TEST(Hypotheses, WeightsMustBeUsable) {
  EXPECT_THROW(position_pmf({}), std::invalid_argument);
  std::vector<TopologicalHypothesis> hs = {hyp({{0, 0}}, 1)};
  hs[0].log_weight = -std::numeric_limits<double>::infinity();
  EXPECT_THROW(position_pmf(hs), std::invalid_argument);
  hs[0].log_weight = std::nan("");
  EXPECT_THROW(normalized_weights(hs), std::invalid_argument);
  hs[0].log_weight = 7;
  EXPECT_EQ(normalized_weights(hs), std::vector<double>{1.0});
}

TEST(Hypotheses, CommonPrefixIsTheSharedHistory) {
  std::vector<TopologicalHypothesis> hs = {
      hyp({{0, 0}, {1, 10}, {2, 20}, {3, 30}}, 1),
      hyp({{0, 0}, {1, 10}, {2, 20}, {0, 30}}, 1),
      hyp({{0, 0}, {1, 10}, {2, 20}, {3, 30}, {4, 40}}, 1)};
  EXPECT_EQ(common_prefix(hs),
            (std::vector<PathEntry>{{0, 0}, {1, 10}, {2, 20}}));
  // The same area entered at another step is a different history.
  hs.push_back(hyp({{0, 0}, {1, 10}, {2, 21}}, 1));
  EXPECT_EQ(common_prefix(hs), (std::vector<PathEntry>{{0, 0}, {1, 10}}));
  hs.push_back(hyp({{5, 0}}, 1));
  EXPECT_TRUE(common_prefix(hs).empty());
  EXPECT_TRUE(common_prefix({}).empty());
}

TEST(Hypotheses, ForgettingKeepsTheDifferencesAndThePosition) {
  std::vector<TopologicalHypothesis> hs = {
      hyp({{0, 0}, {1, 10}, {2, 20}, {3, 30}}, 1),
      hyp({{0, 0}, {1, 10}, {2, 20}, {0, 30}}, 2),
      hyp({{0, 0}, {1, 10}, {2, 20}, {3, 30}, {4, 40}}, 3)};
  EXPECT_EQ(forget_common_history(hs), 3u);
  EXPECT_EQ(hs[0].path, (std::vector<PathEntry>{{3, 30}}));
  EXPECT_EQ(hs[1].path, (std::vector<PathEntry>{{0, 30}}));
  EXPECT_EQ(hs[2].path, (std::vector<PathEntry>{{3, 30}, {4, 40}}));
  EXPECT_EQ(forget_common_history(hs), 0u);
  // The PMF of the position is unchanged by forgetting.
  EXPECT_NEAR(position_pmf(hs).at(0), 2.0 / 6, 1e-15);

  // When every particle agrees on everything, the current entry stays.
  std::vector<TopologicalHypothesis> same = {
      hyp({{0, 0}, {1, 10}, {2, 20}}, 1), hyp({{0, 0}, {1, 10}, {2, 20}}, 1)};
  EXPECT_EQ(forget_common_history(same), 2u);
  EXPECT_EQ(same[0].path, (std::vector<PathEntry>{{2, 20}}));
  EXPECT_EQ(same[1].current_area(), 2u);
}

TEST(Hypotheses, PathsKeepTheirInvariants) {
  TopologicalHypothesis h;
  EXPECT_THROW(h.current_area(), std::logic_error);
  EXPECT_THROW(validate(h), std::invalid_argument);
  enter_area(h, 0, 0);
  enter_area(h, 1, 15);
  EXPECT_EQ(h.current_area(), 1u);
  EXPECT_THROW(enter_area(h, 1, 20), std::invalid_argument);  // same area
  EXPECT_THROW(enter_area(h, 2, 15), std::invalid_argument);  // not later
  EXPECT_THROW(enter_area(h, kNoArea, 30), std::invalid_argument);
  enter_area(h, 0, 16);  // back to area 0: a loop closure
  EXPECT_NO_THROW(validate(h));
  HmtMap m;
  m.add_area(0);
  EXPECT_THROW(validate(h, &m), std::invalid_argument);  // no area 1
  m.add_area(1);
  EXPECT_NO_THROW(validate(h, &m));
  h.path[1].step = 0;
  EXPECT_THROW(validate(h), std::invalid_argument);
}

}  // namespace
}  // namespace hmt::topology

#include "hmt/area/cut_off.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "hmt/area/ncut.h"
#include "hmt/area/sso_graph.h"
#include "sim_world.h"

namespace hmt::area {
namespace {

// The probabilistic SSO over a walk through three rooms, a keyframe every
// 0.9 m.
struct Walk {
  AreaOptions options;
  std::vector<Keyframe> keyframes = sim::three_rooms_walk(0.9);
  Walk() {
    options.sso.use_probabilistic = true;
    options.sso.range_std = 0.02;
    options.index_cell_size = 3.0;
  }
};

// The Ncut of the whole graph, as the area check computed it before:
// every pair matched, keyframes first.
double whole_ncut(const std::vector<Keyframe>& keyframes, const std::vector<Keyframe>& latest,
                  const AreaOptions& o) {
  SsoGraph g(o);
  std::vector<char> in_latest;
  int id = 0;
  for (const Keyframe& k : keyframes) {
    g.add(id++, k);
    in_latest.push_back(0);
  }
  for (const Keyframe& k : latest) {
    g.add(id++, k);
    in_latest.push_back(1);
  }
  return normalized_cut(g.weight_matrix(g.ids()), in_latest);
}

// Over splits of a walk through three rooms (the latest scans in the
// keyframes' room, at its door, in the next room; with and without a
// lasting cache of the keyframes' pairs), and over thresholds on both
// sides of each split's Ncut: the answer is the whole graph's, and where
// the Ncut is well above tau the first latest scans settle it.
TEST(area_CutOff, AnswersAsTheWholeGraphsNcutAndStopsEarlyWhereItCan) {
  const Walk w;
  const AreaOptions& o = w.options;
  const auto& kfs = w.keyframes;
  ASSERT_GE(kfs.size(), 30u);
  auto lasting = std::make_shared<SsoPairCache>();
  int stopped_early = 0, cut = 0, joined = 0;
  for (size_t split : {6u, 10u, 14u, 20u, 26u}) {
    const std::vector<Keyframe> keyframes(kfs.begin(), kfs.begin() + static_cast<long>(split));
    const std::vector<Keyframe> latest(kfs.begin() + static_cast<long>(split),
                                       kfs.begin() + static_cast<long>(split + 4));
    const double ncut = whole_ncut(keyframes, latest, o);
    for (double tau : {0.02, 0.1, 0.3, 0.6, 1.0, 1.5, ncut, ncut + 1e-6}) {
      for (bool with_cache : {false, true}) {
        SCOPED_TRACE("split " + std::to_string(split) + ", tau " + std::to_string(tau) +
                     ", Ncut " + std::to_string(ncut));
        size_t matched = 0;
        const bool off =
            cut_off(keyframes, latest, o, tau, with_cache ? lasting : nullptr, &matched);
        EXPECT_EQ(off, ncut < tau);
        EXPECT_GE(matched, 1u);
        EXPECT_LE(matched, latest.size());
        if (matched < latest.size()) {
          ++stopped_early;
          EXPECT_FALSE(off);
        }
        (off ? cut : joined) += 1;
      }
    }
  }
  // Both answers occur, and some checks were settled by their first scans.
  EXPECT_GT(cut, 0);
  EXPECT_GT(joined, 0);
  EXPECT_GT(stopped_early, 0);
  EXPECT_GT(lasting->hits(), 0u);  // the keyframes' pairs came back
}

TEST(area_CutOff, NothingToCutWithoutKeyframesOrLatestScans) {
  const Walk w;
  const std::vector<Keyframe> some(w.keyframes.begin(), w.keyframes.begin() + 3);
  size_t matched = 7;
  EXPECT_FALSE(cut_off({}, some, w.options, 0.5, nullptr, &matched));
  EXPECT_EQ(matched, 0u);
  EXPECT_FALSE(cut_off(some, {}, w.options, 0.5));
}

}  // namespace
}  // namespace hmt::area

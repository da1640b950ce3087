#include "hmt/area/sso_pair_cache.h"

#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>

#include "hmt/area/sso_graph.h"
#include "sim_world.h"

namespace hmt::area {
namespace {

AreaOptions probabilistic() {
  AreaOptions o;
  o.sso.use_probabilistic = true;
  o.sso.range_std = 0.02;
  o.index_cell_size = 3.0;
  return o;
}

std::vector<Keyframe> walk() {
  std::vector<Keyframe> out;
  const auto all = sim::three_rooms_walk();
  for (size_t i = 0; i < all.size(); i += 6) out.push_back(all[i]);
  for (size_t i = 0; i < out.size(); ++i) out[i].pose.cov.diagonal() << 0.003, 0.002, 1e-4;
  return out;
}

TEST(area_SsoPairCache, KeysFollowEveryPartOfTheKeyframeAndTheOptions) {
  const AreaOptions o = probabilistic();
  const Keyframe k = walk()[3];
  const uint64_t key = keyframe_key(k, o.sso);
  EXPECT_EQ(key, keyframe_key(k, o.sso));
  Keyframe moved = k;
  moved.pose.mean.x += 1e-12;
  EXPECT_NE(keyframe_key(moved, o.sso), key);
  Keyframe wider = k;
  wider.pose.cov(2, 2) *= 2;
  EXPECT_NE(keyframe_key(wider, o.sso), key);
  Keyframe other_range = k;
  other_range.scan.ranges.back() += 0.001f;
  EXPECT_NE(keyframe_key(other_range, o.sso), key);
  ASSERT_FALSE(k.scan.valid.empty());
  Keyframe invalid = k;
  invalid.scan.valid[0] = !invalid.scan.valid[0];
  EXPECT_NE(keyframe_key(invalid, o.sso), key);
  Keyframe later = k;
  later.scan.timestamp += 1.0;
  EXPECT_NE(keyframe_key(later, o.sso), key);
  SsoOptions gate = o.sso;
  gate.gate = 4.0;
  EXPECT_NE(keyframe_key(k, gate), key);
}

TEST(area_SsoPairCache, PairsAreFoundInEitherOrderAndTheCacheStaysBounded) {
  SsoPairCache c(3);
  EXPECT_FALSE(c.find(1, 2));
  c.put(1, 2, 0.25);
  ASSERT_TRUE(c.find(2, 1));
  EXPECT_EQ(*c.find(2, 1), 0.25);
  c.put(3, 4, 0.5);
  c.put(5, 6, 0.75);
  EXPECT_EQ(c.size(), 3u);
  c.put(7, 8, 1.0);  // full: starts afresh
  EXPECT_EQ(c.size(), 1u);
  EXPECT_FALSE(c.find(1, 2));
  EXPECT_TRUE(c.find(8, 7));
  EXPECT_THROW(SsoPairCache(0), std::invalid_argument);
}

// A graph built through the cache is the graph built without it, to the
// bit, whether its pairs were computed or found; the second graph over the
// same keyframes (in another order of addition) matches nothing again.
TEST(area_SsoPairCache, GraphsBuiltThroughTheCacheAreTheSame) {
  const AreaOptions o = probabilistic();
  const auto kfs = walk();
  SsoGraph plain(o);
  for (size_t i = 0; i < kfs.size(); ++i) plain.add(static_cast<int>(i), kfs[i]);
  auto cache = std::make_shared<SsoPairCache>();
  for (int pass = 0; pass < 2; ++pass) {
    SsoGraph g(o);
    g.use_pair_cache(cache);
    const size_t misses = cache->misses();
    for (size_t n = 0; n < kfs.size(); ++n) {
      const size_t i = pass == 0 ? n : kfs.size() - 1 - n;
      g.add(static_cast<int>(i), kfs[i]);
    }
    if (pass == 1) {
      EXPECT_EQ(cache->misses(), misses);
    }
    EXPECT_EQ(g.num_edges(), plain.num_edges());
    for (size_t i = 0; i < kfs.size(); ++i) {
      for (size_t j = 0; j < kfs.size(); ++j) {
        EXPECT_EQ(g.weight(static_cast<int>(i), static_cast<int>(j)),
                  plain.weight(static_cast<int>(i), static_cast<int>(j)))
            << pass << ": " << i << " " << j;
      }
    }
  }
  EXPECT_GT(cache->hits(), plain.num_edges() / 2);
}

// A cache needs every stored keyframe's key: a graph built with one cache
// may go on with another (whose pairs then hold the new keyframes'), one
// whose keyframes were added without a cache takes none; a detached cache
// fills no more.
TEST(area_SsoPairCache, ACacheIsTakenOnlyWhenEveryKeyframeHasItsKey) {
  const auto kfs = walk();
  auto cache = std::make_shared<SsoPairCache>();
  SsoGraph g(probabilistic());
  g.use_pair_cache(cache);
  for (int i = 0; i < 4; ++i) g.add(i, kfs[static_cast<size_t>(i)]);
  const size_t held = cache->size();
  EXPECT_GT(held, 0u);
  auto second = std::make_shared<SsoPairCache>();
  g.use_pair_cache(second);  // every keyframe so far has its key
  g.add(4, kfs[4]);
  EXPECT_EQ(cache->size(), held);
  EXPECT_GT(second->size(), 0u);  // keyframe 4's pairs with 0-3
  g.use_pair_cache(nullptr);
  g.add(5, kfs[5]);
  EXPECT_EQ(cache->size(), held);
  EXPECT_GT(g.num_edges(), 5u);  // the later keyframes still got their edges
  // Keyframe 5 has no key: no cache can be looked up for its pairs.
  EXPECT_THROW(g.use_pair_cache(cache), std::logic_error);
  SsoGraph plain(probabilistic());
  plain.add(0, kfs[0]);
  EXPECT_THROW(plain.use_pair_cache(cache), std::logic_error);
  plain.use_pair_cache(nullptr);  // detaching is always allowed
}

}  // namespace
}  // namespace hmt::area

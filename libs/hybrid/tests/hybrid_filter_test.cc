#include "hmt/hybrid/hybrid_filter.h"

#include <gtest/gtest.h>

#include "ring_world.h"

namespace hmt::hybrid {
namespace {

using testing_ring::expect_ring_closed;
using testing_ring::ring_options;

TEST(HybridFilter, ClosesTheLoopByInference) {
  const auto run = testing_ring::ring_run(7);
  HybridFilter f(ring_options());
  for (const auto& st : run.log.steps) f.process(st);
  EXPECT_EQ(f.stats().steps, run.log.steps.size());
  EXPECT_GE(f.stats().new_area_events, 3u);
  // At some new-area event both "new area" and "area 1 again" were weighed,
  // and area 1 won.
  expect_ring_closed(f);
}

TEST(HybridFilter, HypothesesShareTheParticleBudgetWhenAsked) {
  const auto run = testing_ring::ring_run(7);
  HmtOptions o = ring_options();
  o.hybrid.min_particles = 3;
  // Rival topologies followed and kept even when improbable, so some live
  // beside the winner.
  o.tsbi.min_probability = 1e-9;
  o.hybrid.prune_probability = 1e-9;
  HybridFilter f(o);
  bool shared = false;
  for (const auto& st : run.log.steps) {
    f.process(st);
    const std::vector<double> p = f.probabilities();
    for (size_t i = 0; i < p.size(); ++i) {
      const size_t n = f.hypotheses()[i].filter.particles().size();
      ASSERT_GE(n, 3u);
      ASSERT_LE(n, 10u);
      // A hypothesis holds at least its share (rounded), never less.
      ASSERT_GE(static_cast<double>(n) + 0.5, 10.0 * p[i]);
      shared |= n < 10;
    }
    if (p.size() == 1) ASSERT_EQ(f.hypotheses()[0].filter.particles().size(), 10u);
  }
  EXPECT_TRUE(shared);  // some rival topology ran on fewer particles
}

TEST(HybridFilter, Deterministic) {
  // Half the ring: a few new-area events.
  const auto run = testing_sim::simulate({{2, 2, 0}, {28, 2, 0}, {28, 20, 0}}, 0.3, 9, 0.03,
                                         testing_ring::ring_world(), 10.0);
  HmtOptions o = ring_options();
  HybridFilter a(o);
  o.rbpf.threads = 1;
  HybridFilter b(o);
  for (const auto& st : run.log.steps) {
    a.process(st);
    b.process(st);
  }
  const auto ta = a.final_trajectory(), tb = b.final_trajectory();
  ASSERT_EQ(ta.size(), tb.size());
  for (size_t i = 0; i < ta.size(); ++i) {
    ASSERT_EQ(ta[i].area, tb[i].area);
    ASSERT_EQ(ta[i].poses.size(), tb[i].poses.size());
    for (size_t k = 0; k < ta[i].poses.size(); ++k) {
      EXPECT_EQ(ta[i].poses[k].x, tb[i].poses[k].x);
      EXPECT_EQ(ta[i].poses[k].theta, tb[i].poses[k].theta);
    }
  }
  EXPECT_EQ(a.transitions().size(), b.transitions().size());
  EXPECT_GE(a.transitions().size(), 2u);
}

}  // namespace
}  // namespace hmt::hybrid

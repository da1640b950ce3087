#include "hmt/hybrid/hybrid_filter.h"

#include <gtest/gtest.h>

#include "../../metric_slam/tests/sim_world.h"

namespace hmt::hybrid {
namespace {

using testing_sim::Segment;

// A square ring corridor, 4 m wide, 30 m a side, with pillars and niches so
// no two stretches look alike; the sensor sees 10 m, so the robot meets new
// places as it goes round.
std::vector<Segment> ring_world() {
  std::vector<Segment> w = {{0, 0, 30, 0},  {30, 0, 30, 30}, {30, 30, 0, 30}, {0, 30, 0, 0},
                            {4, 4, 26, 4},  {26, 4, 26, 26}, {26, 26, 4, 26}, {4, 26, 4, 4}};
  auto box = [&](double x, double y, double sx, double sy) {
    w.push_back({x, y, x + sx, y});
    w.push_back({x + sx, y, x + sx, y + sy});
    w.push_back({x + sx, y + sy, x, y + sy});
    w.push_back({x, y + sy, x, y});
  };
  box(7, 0.0, 1.0, 0.6);
  box(13, 3.2, 0.6, 0.8);
  box(20, 0.0, 1.6, 0.5);
  box(29.3, 8, 0.7, 1.2);
  box(26, 15, 0.5, 0.5);
  box(29.5, 22, 0.5, 2.0);
  box(22, 29.4, 1.2, 0.6);
  box(15, 26, 0.4, 0.4);
  box(9, 29.2, 0.5, 0.8);
  box(0, 20, 0.8, 0.8);
  box(3.5, 12, 0.5, 1.5);
  box(0, 6, 0.4, 2.0);
  return w;
}

testing_sim::SimRun ring_run(uint64_t seed) {
  return testing_sim::simulate({{2, 2, 0}, {28, 2, 0}, {28, 28, 0}, {2, 28, 0}, {2, 2, 0},
                                {22, 2, 0}},
                               0.3, seed, 0.03, ring_world(), 10.0);
}

HmtOptions options() {
  HmtOptions o;
  o.rbpf.particles = 10;
  o.rbpf.threads = 2;
  o.rbpf.seed = 3;
  o.area.partition.tau = 0.7;
  return o;
}

TEST(HybridFilter, ClosesTheLoopByInference) {
  const auto run = ring_run(7);
  HybridFilter f(options());
  for (const auto& st : run.log.steps) f.process(st);
  EXPECT_EQ(f.stats().steps, run.log.steps.size());
  EXPECT_GE(f.stats().new_area_events, 3u);
  // At some new-area event both "new area" and "area 1 again" were weighed,
  // and area 1 won.
  bool weighed = false;
  for (const auto& ev : f.transitions()) {
    bool has_new = false, has_one = false;
    for (const auto& o : ev.outcomes) {
      has_new |= o.is_new();
      has_one |= o.area == 1;
    }
    if (has_new && has_one) weighed = true;
  }
  EXPECT_TRUE(weighed);
  const topology::HmtMap map = f.final_map();
  // TLCA accepted a closure into area 1 (from the area where the loop ends,
  // not from area 2 next to it), fine-aligned.
  bool accepted = false;
  for (const auto& a : f.acceptances())
    for (const auto& c : a.closures)
      if (c.record.to == 1 && c.record.from > 2) accepted = c.aligned;
  EXPECT_TRUE(accepted);
  // The loop's arc: area 1 has more than one neighbour.
  EXPECT_GE(map.neighbours(1).size(), 2u);
}

TEST(HybridFilter, Deterministic) {
  // Half the ring: a few new-area events.
  const auto run = testing_sim::simulate({{2, 2, 0}, {28, 2, 0}, {28, 20, 0}}, 0.3, 9, 0.03,
                                         ring_world(), 10.0);
  HmtOptions o = options();
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

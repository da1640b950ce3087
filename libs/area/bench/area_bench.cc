// Cost of the area abstraction on synthetic corridor scans (front 180-degree,
// 361-beam laser, keyframes every 0.5 m):
//  - BM_OnlineKeyframe/<window>: add_keyframe() + update() with the graph full
//    at <window> keyframes (tau = 0 so that no new area ever empties it: the
//    bisection is still computed every time, only never accepted);
//  - BM_OnlineKeyframeProbabilistic/300: the same with the Mahalanobis SSO;
//  - BM_OfflineGrouping/<n>: W over n scans and the recursive partition.
// Targets: online <= 2 ms per keyframe at window 300, growing no faster than
// linearly; offline <= 0.25 s per 100 scans.
#include <benchmark/benchmark.h>

#include <vector>

#include "hmt/area/offline_grouping.h"
#include "hmt/area/online_partitioner.h"
#include "sim_world.h"

namespace hmt::area {
namespace {

constexpr double kStep = 0.5;
constexpr int kTimed = 200;

const std::vector<Keyframe>& corridor_keyframes(int n) {
  static std::vector<Keyframe> cache;
  if (static_cast<int>(cache.size()) < n)
    cache = sim::corridor_walk(n * kStep + 1.0, kStep);
  return cache;
}

void online(benchmark::State& state, bool probabilistic) {
  const int window = static_cast<int>(state.range(0));
  const auto& kfs = corridor_keyframes(window + kTimed);
  AreaOptions o;
  o.window_size = window;
  o.partition.tau = 0.0;
  o.sso.use_probabilistic = probabilistic;
  OnlinePartitioner p(o);
  int next = 0;
  for (; next < window; ++next) p.add_keyframe(kfs[next]);
  size_t candidates = 0, edges = 0;
  for (auto _ : state) {
    p.add_keyframe(kfs[next++]);
    benchmark::DoNotOptimize(p.update());
    candidates += p.graph().last_candidates();
    edges += p.graph().num_edges();
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["window"] = static_cast<double>(p.window().size());
  state.counters["sso_pairs_per_kf"] = candidates / n;
  state.counters["edges"] = edges / n;
}

void BM_OnlineKeyframe(benchmark::State& state) { online(state, false); }
BENCHMARK(BM_OnlineKeyframe)
    ->Arg(50)
    ->Arg(100)
    ->Arg(200)
    ->Arg(300)
    ->Arg(500)
    ->Iterations(kTimed)
    ->Unit(benchmark::kMillisecond);

// The same with the Mahalanobis SSO of 000 Eq. 16 (exact poses, sampling and
// range noise only): pairwise matches against the keyframes whose boxes
// overlap.
void BM_OnlineKeyframeProbabilistic(benchmark::State& state) {
  online(state, true);
}
BENCHMARK(BM_OnlineKeyframeProbabilistic)
    ->Arg(300)
    ->Iterations(50)
    ->Unit(benchmark::kMillisecond);

void BM_OfflineGrouping(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const auto& all = corridor_keyframes(n);
  const std::vector<Keyframe> kfs(all.begin(), all.begin() + n);
  AreaOptions o;
  size_t groups = 0;
  for (auto _ : state) {
    const Grouping g = group_keyframes(kfs, o);
    groups = g.groups.size();
    benchmark::DoNotOptimize(g.W.nonZeros());
  }
  state.counters["groups"] = static_cast<double>(groups);
  state.counters["scans"] = n;
}
BENCHMARK(BM_OfflineGrouping)
    ->Arg(100)
    ->Arg(300)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace hmt::area

BENCHMARK_MAIN();

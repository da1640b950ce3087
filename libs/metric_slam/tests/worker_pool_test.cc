#include "hmt/metric_slam/worker_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>

namespace hmt::metric_slam {
namespace {

TEST(WorkerPool, VisitsEveryIndexOnce) {
  WorkerPool pool(3);
  for (int round = 0; round < 50; ++round) {
    std::vector<std::atomic<int>> hits(97);
    pool.parallel_for(hits.size(), [&](size_t i) { hits[i]++; });
    for (auto& h : hits) ASSERT_EQ(h.load(), 1);
  }
}

TEST(WorkerPool, PropagatesExceptions) {
  WorkerPool pool(2);
  EXPECT_THROW(pool.parallel_for(10, [](size_t i) {
                 if (i == 7) throw std::runtime_error("boom");
               }),
               std::runtime_error);
  // Still usable afterwards.
  std::atomic<int> n{0};
  pool.parallel_for(5, [&](size_t) { n++; });
  EXPECT_EQ(n.load(), 5);
}

}  // namespace
}  // namespace hmt::metric_slam

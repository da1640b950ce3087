#include "hmt/common/worker_pool.h"

#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include <atomic>
#include <stdexcept>

namespace hmt {
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

TEST(WorkerPool, CallersOnSeveralThreadsTakeTurns) {
  WorkerPool pool(3);
  std::vector<std::vector<int>> seen(4, std::vector<int>(500, 0));
  std::vector<std::thread> callers;
  for (size_t c = 0; c < seen.size(); ++c)
    callers.emplace_back([&, c] {
      for (int rep = 0; rep < 20; ++rep)
        pool.parallel_for(seen[c].size(), [&](size_t i) { ++seen[c][i]; });
    });
  for (auto& t : callers) t.join();
  for (const auto& v : seen)
    for (int x : v) EXPECT_EQ(x, 20);
}

}  // namespace
}  // namespace hmt

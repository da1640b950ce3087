#include "hmt/framework/bounded_queue.h"

#include <gtest/gtest.h>

#include <thread>
#include <vector>

namespace hmt::framework {
namespace {

TEST(BoundedQueue, KeepsOrderAcrossThreadsAndNeverHoldsMoreThanItsCapacity) {
  BoundedQueue<int> q(3);
  size_t max_seen = 0;
  std::vector<int> got;
  std::thread consumer([&] {
    while (std::optional<int> v = q.pop()) {
      max_seen = std::max(max_seen, q.size());
      got.push_back(*v);
    }
  });
  for (int i = 0; i < 1000; ++i) ASSERT_TRUE(q.push(i));
  q.close();
  consumer.join();
  ASSERT_EQ(got.size(), 1000u);
  for (int i = 0; i < 1000; ++i) EXPECT_EQ(got[static_cast<size_t>(i)], i);
  EXPECT_LE(max_seen, 3u);
}

TEST(BoundedQueue, CloseWakesAWaitingConsumerAndRefusesPushes) {
  BoundedQueue<int> q(2);
  std::optional<int> result = 7;
  std::thread consumer([&] { result = q.pop(); });
  q.close();
  consumer.join();
  EXPECT_FALSE(result.has_value());
  EXPECT_FALSE(q.push(1));
  EXPECT_TRUE(q.closed());
}

TEST(BoundedQueue, CloseWakesAWaitingProducer) {
  BoundedQueue<int> q(1);
  ASSERT_TRUE(q.push(1));
  bool pushed = true;
  std::thread producer([&] { pushed = q.push(2); });  // waits: the queue is full
  q.close();
  producer.join();
  EXPECT_FALSE(pushed);
  // What was queued before closing is still delivered.
  EXPECT_EQ(q.pop(), std::optional<int>(1));
  EXPECT_FALSE(q.pop().has_value());
}

TEST(BoundedQueue, DiscardingCloseDropsTheQueuedItems) {
  BoundedQueue<int> q(4);
  q.push(1);
  q.push(2);
  q.close(/*discard=*/true);
  EXPECT_FALSE(q.pop().has_value());
  EXPECT_FALSE(q.try_pop().has_value());
}

TEST(BoundedQueue, TryPopNeverWaits) {
  BoundedQueue<int> q(2);
  EXPECT_FALSE(q.try_pop().has_value());
  q.push(5);
  EXPECT_EQ(q.try_pop(), std::optional<int>(5));
}

}  // namespace
}  // namespace hmt::framework

#include "hmt/framework/process.h"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <vector>

namespace hmt::framework {
namespace {

TEST(Process, HandlesEveryMessageInOrderBeforeStopReturns) {
  std::vector<int> seen;  // written by the process's thread, read after stop()
  Process<int> p("test", 2, [&](int& m) { seen.push_back(m); });
  p.start();
  for (int i = 0; i < 100; ++i) ASSERT_TRUE(p.post(i));
  p.stop();
  ASSERT_EQ(seen.size(), 100u);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(seen[static_cast<size_t>(i)], i);
  EXPECT_FALSE(p.error());
  EXPECT_FALSE(p.post(1));  // stopped
}

TEST(Process, AFailingHandlerStopsTheProcessAndReportsItsError) {
  std::atomic<int> failures{0};
  Process<int> p(
      "test", 4,
      [](int& m) {
        if (m == 3) throw std::runtime_error("bad message 3");
      },
      [&] { ++failures; });
  p.start();
  for (int i = 0; i < 3; ++i) p.post(i);
  p.post(3);
  p.stop();
  ASSERT_TRUE(p.error());
  EXPECT_EQ(failures.load(), 1);
  try {
    std::rethrow_exception(p.error());
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "bad message 3");
  }
  EXPECT_FALSE(p.post(4));
}

TEST(Process, StoppingANeverStartedProcessDoesNotBlock) {
  Process<int> p("idle", 1, [](int&) {});
  p.stop();
  EXPECT_FALSE(p.post(1));
}

}  // namespace
}  // namespace hmt::framework

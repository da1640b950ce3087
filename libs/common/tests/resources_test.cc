#include "hmt/common/resources.h"

#include <gtest/gtest.h>

#include <malloc.h>

#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace hmt {
namespace {

#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
// glibc marks a chunk it mapped on its own with bit 1 (IS_MMAPPED) of the
// size word just before the user pointer.
bool is_own_mapping(void* p) {
  size_t size_word = 0;
  const auto header = reinterpret_cast<const void*>(reinterpret_cast<uintptr_t>(p) - sizeof(size_t));
  std::memcpy(&size_word, header, sizeof size_word);
  return (size_word & 2u) != 0;
}

TEST(Resources, FreedLargeBlocksDoNotRaiseTheMmapThreshold) {
  // GLIBC_TUNABLES would make the call a no-op (the user's choice).
  const char* t = std::getenv("GLIBC_TUNABLES");
  if (t && std::strstr(t, "malloc.mmap_threshold")) GTEST_SKIP() << "GLIBC_TUNABLES sets it";
  tune_allocator();
  // Without the fix, freeing a 4 MiB mapping lifts glibc's threshold past
  // 4 MiB, and the 256 KiB block below would come from the heap.
  void* big = std::malloc(4 << 20);
  ASSERT_NE(big, nullptr);
  std::memset(big, 1, 4 << 20);
  std::free(big);
  void* mid = std::malloc(256 << 10);
  ASSERT_NE(mid, nullptr);
  EXPECT_TRUE(is_own_mapping(mid));
  std::free(mid);
}

// The arenas glibc has made so far: malloc_info() lists one <heap> each.
int arenas() {
  char* text = nullptr;
  size_t size = 0;
  FILE* f = open_memstream(&text, &size);
  if (!f) return -1;
  malloc_info(0, f);
  std::fclose(f);
  int n = 0;
  for (const char* p = text; (p = std::strstr(p, "<heap nr=")) != nullptr; ++p) ++n;
  std::free(text);
  return n;
}

TEST(Resources, ThreadsShareAtMostTwoArenas) {
  const char* t = std::getenv("GLIBC_TUNABLES");
  if ((t && std::strstr(t, "malloc.arena_max")) || std::getenv("MALLOC_ARENA_MAX"))
    GTEST_SKIP() << "the environment sets the arenas";
  tune_allocator();
  // Six threads allocating at once, each holding its block until all have
  // one: glibc's default would give most of them an arena of their own.
  constexpr int kThreads = 6;
  std::mutex m;
  std::condition_variable cv;
  int holding = 0;
  std::vector<std::thread> threads;
  for (int i = 0; i < kThreads; ++i)
    threads.emplace_back([&] {
      void* p = std::malloc(1000);
      std::memset(p, 1, 1000);
      std::unique_lock<std::mutex> lock(m);
      ++holding;
      cv.notify_all();
      cv.wait(lock, [&] { return holding == kThreads; });
      lock.unlock();
      std::free(p);
    });
  for (auto& th : threads) th.join();
  EXPECT_GE(arenas(), 1);
  EXPECT_LE(arenas(), 2);
}

TEST(Resources, ReleaseReturnsFreePagesPinnedBelowALiveBlock) {
  // 64 MiB of small blocks, then one small block after them that stays:
  // freeing the 64 MiB leaves them free in the middle of the heap, where
  // free() alone keeps them resident.
  constexpr size_t kBlocks = 256 * 1024, kSize = 256;
  std::vector<void*> blocks(kBlocks);
  for (void*& p : blocks) {
    p = std::malloc(kSize);
    ASSERT_NE(p, nullptr);
    std::memset(p, 1, kSize);
  }
  void* pin = std::malloc(kSize);
  ASSERT_NE(pin, nullptr);
  std::memset(pin, 1, kSize);
  for (void* p : blocks) std::free(p);
  const size_t before = current_rss_bytes();
  release_free_memory();
  const size_t after = current_rss_bytes();
  std::free(pin);
  EXPECT_LT(after + (32u << 20), before) << "before " << before << " after " << after;
}
#endif

TEST(Resources, TrimmerWaitsItsSpacingBetweenReleases) {
  MemoryTrimmer t(100);
  EXPECT_FALSE(t.maybe_release(0));
  EXPECT_FALSE(t.maybe_release(99));
  EXPECT_TRUE(t.maybe_release(100));
  EXPECT_FALSE(t.maybe_release(150));
  EXPECT_FALSE(t.maybe_release(199));
  EXPECT_TRUE(t.maybe_release(230));
  EXPECT_FALSE(t.maybe_release(329));
  EXPECT_TRUE(t.maybe_release(330));
}

TEST(Resources, PeakIsAtLeastCurrent) {
  EXPECT_GT(current_rss_bytes(), 0u);
  EXPECT_GE(peak_rss_bytes(), current_rss_bytes());
}

}  // namespace
}  // namespace hmt

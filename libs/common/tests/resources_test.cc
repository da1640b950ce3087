#include "hmt/common/resources.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>

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
  fix_allocator_mmap_threshold();
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
#endif

TEST(Resources, PeakIsAtLeastCurrent) {
  EXPECT_GT(current_rss_bytes(), 0u);
  EXPECT_GE(peak_rss_bytes(), current_rss_bytes());
}

}  // namespace
}  // namespace hmt

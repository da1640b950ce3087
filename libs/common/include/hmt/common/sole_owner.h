// Copy-on-write with std::shared_ptr: an object whose use count is 1 may be
// written in place, but another thread may have just released its copy
// after reading it. acquire_sole_ownership() pairs with that release before
// the write. ThreadSanitizer ignores fences, so under it the acquire goes
// through the use count itself (a copy and its release are acquire-release
// read-modify-writes of the count).
#pragma once

#include <atomic>
#include <memory>

#if defined(__SANITIZE_THREAD__)
#define HMT_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define HMT_TSAN 1
#endif
#endif
#ifndef HMT_TSAN
#define HMT_TSAN 0
#endif

namespace hmt {

// Call when `p.use_count() == 1`, before writing through it.
template <class T>
void acquire_sole_ownership(const std::shared_ptr<T>& p) {
#if HMT_TSAN
  std::shared_ptr<T>(p).reset();
#else
  (void)p;
  std::atomic_thread_fence(std::memory_order_acquire);
#endif
}

}  // namespace hmt

#include "hmt/common/resources.h"

#include <sys/resource.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace hmt {
namespace {

// Reads a "Key:   1234 kB" line of /proc/self/status; 0 if unavailable.
size_t proc_status_kb(const char* key) {
  FILE* f = std::fopen("/proc/self/status", "r");
  if (!f) return 0;
  char line[256];
  size_t kb = 0;
  const size_t n = std::strlen(key);
  while (std::fgets(line, sizeof line, f)) {
    if (std::strncmp(line, key, n) == 0) {
      std::sscanf(line + n, " %zu", &kb);
      break;
    }
  }
  std::fclose(f);
  return kb;
}

}  // namespace

size_t peak_rss_bytes() {
  size_t kb = proc_status_kb("VmHWM:");
  if (kb == 0) {
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    kb = static_cast<size_t>(ru.ru_maxrss);
  }
  return kb * 1024;
}

size_t current_rss_bytes() { return proc_status_kb("VmRSS:") * 1024; }

void tune_allocator() {
#if defined(__GLIBC__)
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  const auto user_set = [&](const char* tunable) {
    return tunables && std::strstr(tunables, tunable);
  };
  // Setting M_MMAP_THRESHOLD also turns glibc's dynamic adjustment off.
  if (!user_set("malloc.mmap_threshold")) mallopt(M_MMAP_THRESHOLD, 128 * 1024);
  if (!user_set("malloc.arena_max") && !std::getenv("MALLOC_ARENA_MAX")) mallopt(M_ARENA_MAX, 2);
#endif
}

void release_free_memory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

bool MemoryTrimmer::maybe_release(uint64_t step) {
  if (step < last_ + spacing_) return false;
  last_ = step;
  release_free_memory();
  return true;
}

}  // namespace hmt

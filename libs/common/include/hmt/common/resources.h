// Process resource figures for summaries and benchmarks.
#pragma once

#include <cstddef>

namespace hmt {

// Peak resident set size of this process so far, in bytes (VmHWM).
size_t peak_rss_bytes();
// Current resident set size, in bytes (VmRSS).
size_t current_rss_bytes();

// Keeps glibc's mmap threshold at its initial 128 KiB instead of letting it
// rise. Why: glibc raises the threshold to the size of every mmapped block
// that is freed (up to 32 MiB), after which the large, short-lived buffers of
// a run (tile tables, TSBI match fields and cost stacks, the branch and
// bound's frontier, scratch grids) are carved from the arenas of the five
// processes' and the workers' threads; freed, they leave holes that the
// small, long-lived map tiles then pin, and the resident size ratchets up.
// With the threshold fixed each such buffer is its own mapping, returned to
// the system when freed: 20 MB (12 %) less peak memory on the Infinite
// Corridor, at no measurable cost in time. Does nothing when the user set
// the threshold through GLIBC_TUNABLES (glibc.malloc.mmap_threshold), or on
// a C library other than glibc. Call once, first thing in main().
void fix_allocator_mmap_threshold();

}  // namespace hmt

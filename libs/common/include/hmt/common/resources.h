// Process resource figures for summaries and benchmarks.
#pragma once

#include <cstddef>

namespace hmt {

// Peak resident set size of this process so far, in bytes (VmHWM).
size_t peak_rss_bytes();
// Current resident set size, in bytes (VmRSS).
size_t current_rss_bytes();

// Two settings of glibc's allocator, for the way this program allocates.
// Call once, first thing in main(); each does nothing when the user made it
// through GLIBC_TUNABLES (or MALLOC_ARENA_MAX), or on a C library other
// than glibc.
//
// The mmap threshold stays at its initial 128 KiB instead of rising. glibc
// raises it to the size of every mmapped block that is freed (up to
// 32 MiB), after which the large, short-lived buffers of a run (tile
// tables, TSBI match fields and cost stacks, the branch and bound's
// frontier, scratch grids) are carved from the arenas of the five
// processes' and the workers' threads; freed, they leave holes that the
// small, long-lived map tiles then pin, and the resident size ratchets up.
// With the threshold fixed each such buffer is its own mapping, returned
// to the system when freed: 20 MB (12 %) less peak memory on the Infinite
// Corridor, at no measurable cost in time.
//
// At most two arenas. By default glibc gives each thread that finds the
// others' arenas busy one of its own, up to eight per core; the map tiles
// and scans one thread allocates are then often freed by another, and each
// arena keeps its own free lists and its own partly used pages. With two
// the threads reuse each other's freed memory: 1-14 % less peak on the
// shared logs (intel 62 to 56 MB, the five-lap soak 158 to 150-154 MB) in the
// same time, the threads' hot loops allocating next to nothing.
void tune_allocator();

}  // namespace hmt

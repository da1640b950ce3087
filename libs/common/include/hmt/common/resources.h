// Process resource figures for summaries and benchmarks.
#pragma once

#include <cstddef>
#include <cstdint>

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

// Hands the free pages inside the allocator's arenas back to the system
// (glibc's malloc_trim; nothing elsewhere).
//
// The map tiles that particles share and drop are small blocks, freed in
// scattered places; the pages they leave free are reused by later tiles
// but stay resident meanwhile. So without this the resident size of a long
// run ratchets up with each transient (a topological event's children, its
// match fields and cost stacks) while the live heap does not: on the
// five-lap soak (scripts/bench_soak.sh) the peak went from 131-136 MB after
// lap 1 to 146-150 MB after lap 5, while the heap itself (heaptrack) never
// again reached lap 1's peak before lap 5.
void release_free_memory();

// release_free_memory() at most once every `spacing` steps (when asked).
// A trim costs about 10 ms on a 100 MB heap (it returns every free page,
// and later allocations fault them in again): once every 250 steps, at 4-10
// ms a step, keeps that under 1 % of a run.
class MemoryTrimmer {
 public:
  explicit MemoryTrimmer(uint64_t spacing = 250) : spacing_(spacing) {}
  // Trims if `step` is at least `spacing` steps after the last trim (or,
  // before any, after step 0); returns whether it did.
  bool maybe_release(uint64_t step);

 private:
  uint64_t spacing_;
  uint64_t last_ = 0;
};

}  // namespace hmt

// Process resource figures for summaries and benchmarks.
#pragma once

#include <cstddef>

namespace hmt {

// Peak resident set size of this process so far, in bytes (VmHWM).
size_t peak_rss_bytes();
// Current resident set size, in bytes (VmRSS).
size_t current_rss_bytes();

}  // namespace hmt

// The rate of a count over its last few seconds, for a progress line's ETA.
// On a long log the cost of a scan grows as the map does (more known areas
// for each new-area event to weigh), so the average since the start promises
// too early an end; the rate over a recent window follows the slowdown.
#pragma once

#include <cstddef>
#include <deque>
#include <utility>

namespace hmt {

class RecentRate {
 public:
  // `window_s`: how far back the rate looks (seconds, > 0).
  explicit RecentRate(double window_s);
  // `t`: seconds since the count began (never decreasing); `done`: the count
  // then. Cheap on every item: samples are kept 1/32 of the window apart.
  void add(double t, size_t done);
  // Items a second from the oldest kept sample (the one at or just before
  // the window's start, the first until the window is full) to the newest;
  // 0 until two samples span some time.
  double rate() const;
  // Samples held: at most about 33, however long the count runs.
  size_t kept() const { return samples_.size(); }

 private:
  double window_s_;
  std::deque<std::pair<double, size_t>> samples_;  // (t, done), oldest first
};

}  // namespace hmt

#include "hmt/common/recent_rate.h"

namespace hmt {

RecentRate::RecentRate(double window_s) : window_s_(window_s) {}

void RecentRate::add(double t, size_t done) {
  // The newest sample always holds the latest count; a new one starts only
  // 1/32 of the window after the one before, so the deque stays short.
  if (samples_.size() >= 2 && t - samples_[samples_.size() - 2].first < window_s_ / 32.0)
    samples_.back() = {t, done};
  else
    samples_.emplace_back(t, done);
  // Keep one sample at or before the window's start: the rate spans the
  // whole window, not less.
  while (samples_.size() >= 2 && samples_[1].first <= t - window_s_) samples_.pop_front();
}

double RecentRate::rate() const {
  if (samples_.size() < 2) return 0.0;
  const auto& [t0, n0] = samples_.front();
  const auto& [t1, n1] = samples_.back();
  if (t1 <= t0 || n1 < n0) return 0.0;
  return static_cast<double>(n1 - n0) / (t1 - t0);
}

}  // namespace hmt

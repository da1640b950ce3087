#include "hmt/common/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>

namespace hmt {
namespace {
using Clock = std::chrono::steady_clock;
double seconds(Clock::duration d) {
  return std::chrono::duration<double>(d).count();
}
std::string hms(double s) {
  if (!std::isfinite(s) || s < 0) return "--:--";
  const long t = static_cast<long>(s + 0.5);
  char buf[32];
  if (t >= 3600)
    std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", t / 3600, (t / 60) % 60, t % 60);
  else
    std::snprintf(buf, sizeof buf, "%02ld:%02ld", t / 60, t % 60);
  return buf;
}
}  // namespace

Progress::Progress(std::string unit, size_t total, FILE* out,
                   double plain_interval_s)
    : unit_(std::move(unit)),
      total_(total),
      out_(out),
      tty_(::isatty(::fileno(out)) != 0),
      interval_s_(plain_interval_s),
      start_(Clock::now()),
      last_(start_) {}

std::string Progress::line(size_t done, const std::string& extra) const {
  const double el = seconds(Clock::now() - start_);
  // The recent rate, the average since the start until it has one.
  const double recent = recent_.rate();
  const double rate = recent > 0 ? recent : el > 0 ? done / el : 0.0;
  // Of the whole: done / total, or the share given when the total is unknown.
  const double share = total_ ? static_cast<double>(done) / static_cast<double>(total_)
                              : std::clamp(fraction_, 0.0, 1.0);
  double eta = rate > 0 && total_ >= done ? (total_ - done) / rate : NAN;
  if (!total_) eta = share > 0 ? el * (1.0 - share) / share : NAN;
  char buf[256];
  std::string bar;
  if (tty_) {
    const int width = 30;
    const int fill = total_ ? static_cast<int>(width * done / total_)
                            : static_cast<int>(width * share);
    bar = "[" + std::string(fill, '#') + std::string(width - fill, '.') + "] ";
  }
  if (total_)
    std::snprintf(buf, sizeof buf, "%zu/%zu %s  %.1f %s/s  ETA %s", done, total_,
                  unit_.c_str(), rate, unit_.c_str(), hms(eta).c_str());
  else
    std::snprintf(buf, sizeof buf, "%zu %s (%.0f%% of the input)  %.1f %s/s  ETA %s", done,
                  unit_.c_str(), 100.0 * share, rate, unit_.c_str(), hms(eta).c_str());
  std::string s = bar + buf;
  if (!extra.empty()) s += "  " + extra;
  return s;
}

void Progress::update(size_t done, const std::string& extra) {
  done_ = done;
  if (!enabled_) return;
  const auto now = Clock::now();
  recent_.add(seconds(now - start_), done);
  const double since = seconds(now - last_);
  if (tty_) {
    if (since < 0.1 && done != total_) return;
    std::fprintf(out_, "\r\033[K%s", line(done, extra).c_str());
  } else {
    if (since < interval_s_) return;
    std::fprintf(out_, "%s\n", line(done, extra).c_str());
  }
  std::fflush(out_);
  last_ = now;
}

void Progress::finish(const std::string& extra) {
  if (!enabled_) return;
  const double el = seconds(Clock::now() - start_);
  if (tty_) std::fprintf(out_, "\r\033[K");
  std::fprintf(out_, "done: %zu %s in %s (%.1f %s/s)%s%s\n", done_,
               unit_.c_str(), hms(el).c_str(), el > 0 ? done_ / el : 0.0,
               unit_.c_str(), extra.empty() ? "" : "  ", extra.c_str());
  std::fflush(out_);
}

}  // namespace hmt

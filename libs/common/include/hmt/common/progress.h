// Progress of a long run on stderr: a bar redrawn in place on a terminal
// (done/total, rate, ETA and caller-supplied fields), one plain line every few
// seconds otherwise (logs, CI). The rate and the ETA are those of the last
// 30 seconds (RecentRate): a scan costs more as the map grows.
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

#include "hmt/common/recent_rate.h"

namespace hmt {

class Progress {
 public:
  // `unit` names what is counted ("scans"). `out` defaults to stderr.
  // `total` 0: unknown (a log read as it goes); the bar and the ETA then
  // follow the share given to set_fraction().
  Progress(std::string unit, size_t total, FILE* out = stderr,
           double plain_interval_s = 5.0);
  // Reports `done` items so far; `extra` is appended (e.g. "areas 3").
  void update(size_t done, const std::string& extra = "");
  // With an unknown total: how much of the work is done, in [0, 1] (e.g.
  // the share of the input file read).
  void set_fraction(double fraction) { fraction_ = fraction; }
  // Final line (always printed).
  void finish(const std::string& extra = "");
  void set_enabled(bool on) { enabled_ = on; }

 private:
  std::string line(size_t done, const std::string& extra) const;

  std::string unit_;
  size_t total_;
  FILE* out_;
  bool tty_;
  bool enabled_ = true;
  double interval_s_;
  size_t done_ = 0;
  double fraction_ = 0.0;
  std::chrono::steady_clock::time_point start_, last_;
  RecentRate recent_{30.0};
};

}  // namespace hmt

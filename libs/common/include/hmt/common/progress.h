// Progress of a long run on stderr: a bar redrawn in place on a terminal
// (done/total, rate, ETA and caller-supplied fields), one plain line every few
// seconds otherwise (logs, CI).
#pragma once

#include <chrono>
#include <cstdio>
#include <string>

namespace hmt {

class Progress {
 public:
  // `unit` names what is counted ("scans"). `out` defaults to stderr.
  Progress(std::string unit, size_t total, FILE* out = stderr,
           double plain_interval_s = 5.0);
  // Reports `done` items so far; `extra` is appended (e.g. "areas 3").
  void update(size_t done, const std::string& extra = "");
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
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace hmt

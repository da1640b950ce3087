// What the fuzz targets share: a scratch file for the readers that take a
// path, and the checks that turn a wrong result into a finding.
//
// A reader may refuse its input only with one of the project's errors
// (hmt::Error: a clear message and exit code). Anything else -- a sanitizer
// report, another exception, a result that breaks the documented invariants
// -- aborts the run, which libFuzzer reports as a crash with the input.
#pragma once

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "hmt/common/sensor_data.h"

namespace hmt::fuzz {

[[noreturn]] inline void finding(const std::string& what) {
  std::fprintf(stderr, "fuzz finding: %s\n", what.c_str());
  std::abort();
}

inline void check(bool ok, const std::string& what) {
  if (!ok) finding(what);
}

// A file of this process in the temporary folder, removed at exit; the
// readers under test take paths (gzip detection, format sniffing and all).
class ScratchFile {
 public:
  explicit ScratchFile(const std::string& name)
      : path_((std::filesystem::temp_directory_path() /
               ("hmt-fuzz-" + std::to_string(::getpid()) + "-" + name))
                  .string()) {}
  ~ScratchFile() { std::remove(path_.c_str()); }

  // Replaces the file's content with the input.
  const std::string& write(const uint8_t* data, size_t size) {
    std::FILE* f = std::fopen(path_.c_str(), "wb");
    check(f != nullptr, "cannot create the scratch file " + path_);
    const bool ok = std::fwrite(data, 1, size, f) == size;
    check(std::fclose(f) == 0 && ok, "cannot write the scratch file " + path_);
    return path_;
  }

 private:
  std::string path_;
};

inline bool finite(const Pose2D& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.theta);
}

// What every reader promises of a log it returns (sensor_data.h, rawlog.h,
// carmen.h): steps with scans of matching ranges and flags, finite geometry
// and times, no NaN or negative reading, valid readings below max_range.
inline void check_log(const hmt::Log& log) {
  check(!log.steps.empty(), "a log without steps was returned");
  for (size_t k = 0; k < log.steps.size(); ++k) {
    const LogStep& s = log.steps[k];
    const LaserScan& scan = s.scan;
    const std::string at = "step " + std::to_string(k) + ": ";
    check(std::isfinite(s.timestamp), at + "non-finite timestamp");
    check(s.has_odometry == (k > 0), at + "odometry flag");
    check(finite(s.odometry_increment), at + "non-finite odometry increment");
    check(!scan.ranges.empty(), at + "scan without beams");
    check(scan.valid.size() == scan.ranges.size(), at + "ranges and flags differ in number");
    check(std::isfinite(scan.max_range) && scan.max_range > 0.0f, at + "max_range not finite positive");
    check(std::isfinite(scan.angle_min) && std::isfinite(scan.angle_increment),
          at + "non-finite beam angles");
    check(std::isfinite(scan.bearing(scan.size() - 1)), at + "non-finite last bearing");
    check(finite(scan.sensor_pose), at + "non-finite sensor pose");
    for (size_t i = 0; i < scan.size(); ++i) {
      const float r = scan.ranges[i];
      check(!std::isnan(r) && r >= 0.0f, at + "NaN or negative reading");
      if (scan.valid[i])
        check(r > 0.0f && r < scan.max_range, at + "valid reading outside (0, max_range)");
    }
  }
}

}  // namespace hmt::fuzz

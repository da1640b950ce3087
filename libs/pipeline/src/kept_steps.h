// What the HMT job keeps of its log, which it reads as the run goes
// (input_steps.h) rather than holding it: every step's timestamp and
// odometry (33 bytes a step), and after the run the keyframes' scans, read
// from the log a second time.
#pragma once

#include <cstdint>
#include <map>
#include <set>
#include <vector>

#include "hmt/common/sensor_data.h"
#include "hmt/pipeline/input_steps.h"

namespace hmt::pipeline {

struct KeptSteps {
  std::vector<double> timestamps;     // trajectory.tum's clock
  std::vector<Pose2D> odometry;       // the keyframe graph's motion between
  std::vector<uint8_t> has_odometry;  // keyframes where no path covers it

  void add(const LogStep& step);
  // Step k (0: the first of the log) without its scan.
  LogStep bare_step(size_t k) const;
};

// Reads the log again from `open` (selected by `input` as on the first
// reading) and returns the steps numbered in `wanted`, whole; steps are
// numbered from `first_step`. Throws InputError if the log no longer begins
// with the `count` steps whose checkpoint::log_fingerprint() is `log_crc`:
// the file was changed since the first reading.
std::map<uint64_t, LogStep> read_steps_again(const LogOpener& open, const InputOptions& input,
                                             uint64_t first_step, size_t count,
                                             uint32_t log_crc, const std::set<uint64_t>& wanted);

}  // namespace hmt::pipeline

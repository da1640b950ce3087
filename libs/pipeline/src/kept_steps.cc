#include "kept_steps.h"

#include "hmt/checkpoint/checkpoint.h"
#include "hmt/common/error.h"

namespace hmt::pipeline {

void KeptSteps::add(const LogStep& step) {
  timestamps.push_back(step.timestamp);
  odometry.push_back(step.odometry_increment);
  has_odometry.push_back(step.has_odometry ? 1 : 0);
}

LogStep KeptSteps::bare_step(size_t k) const {
  LogStep s;
  s.timestamp = timestamps[k];
  s.odometry_increment = odometry[k];
  s.has_odometry = has_odometry[k] != 0;
  return s;
}

std::map<uint64_t, LogStep> read_steps_again(const LogOpener& open, const InputOptions& input,
                                             uint64_t first_step, size_t count,
                                             uint32_t log_crc, const std::set<uint64_t>& wanted) {
  // The run checked the odometry as it read the log; this reading checks
  // the log is that one.
  InputSteps steps(open(), input, /*check_odometry=*/false);
  const auto changed = [&] {
    return InputError("the log '" + steps.source() +
                      "' changed during the run: read again for the keyframes' scans, it no "
                      "longer begins with the " + std::to_string(count) + " scans processed");
  };
  std::map<uint64_t, LogStep> out;
  uint32_t crc = 0;
  LogStep step;
  for (size_t k = 0; k < count; ++k) {
    if (!steps.next(step)) throw changed();
    crc = checkpoint::log_fingerprint(crc, step);
    if (wanted.count(first_step + k)) out.emplace(first_step + k, std::move(step));
  }
  if (crc != log_crc) throw changed();
  return out;
}

}  // namespace hmt::pipeline

#include "hmt/pipeline/input_steps.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "hmt/common/error.h"
#include "frozen_odometry.h"
#include "odometry_turns.h"

namespace hmt::pipeline {

InputSteps::InputSteps(std::unique_ptr<io::LogStream> stream, const InputOptions& input,
                       bool check_odometry)
    : io::LogStream(stream->source()), stream_(std::move(stream)), input_(input) {
  if (check_odometry) {
    frozen_ = std::make_unique<FrozenOdometryCheck>();
    turns_ = std::make_unique<OdometryTurnsCheck>();
  }
}

InputSteps::~InputSteps() = default;

bool InputSteps::pull() {
  LogStep step;
  if (!skipped_) {
    skipped_ = true;
    for (int k = 0; k < input_.first_step; ++k)
      if (!stream_->next(step)) return false;
  }
  if (input_.max_steps > 0 && pulled_ >= static_cast<size_t>(input_.max_steps)) return false;
  if (!stream_->next(step)) return false;
  const size_t index = static_cast<size_t>(input_.first_step) + pulled_;  // in the log
  const Pose2D& d = step.odometry_increment;
  const double motion = std::hypot(d.x, d.y);
  if (step.has_odometry && !(motion <= input_.max_step_motion)) {
    char m[96];
    std::snprintf(m, sizeof m, "%.3g m in one step, more than [input] max_step_motion = %g m",
                  motion, input_.max_step_motion);
    throw InputError("log '" + source() + "' step " + std::to_string(index) +
                     ": the odometry moves the robot " + m + " (broken odometry?)");
  }
  if (frozen_) {
    frozen_->add(step, index, source());
    turns_->add(step, index, source());
  }
  ++pulled_;
  ahead_.push_back(std::move(step));
  return true;
}

std::optional<size_t> InputSteps::total_steps() const {
  const std::optional<size_t> all = stream_->total_steps();
  if (!all) return std::nullopt;
  const size_t first = static_cast<size_t>(input_.first_step);
  size_t n = *all > first ? *all - first : 0;
  if (input_.max_steps > 0) n = std::min(n, static_cast<size_t>(input_.max_steps));
  return n;
}

double InputSteps::fraction_read() const {
  double f = stream_->fraction_read();
  if (input_.max_steps > 0)
    f = std::max(f, static_cast<double>(pulled_) / static_cast<double>(input_.max_steps));
  return std::min(f, 1.0);
}

const LogStep* InputSteps::peek(size_t ahead) {
  while (ahead_.size() <= ahead)
    if (!pull()) return nullptr;
  return &ahead_[ahead];
}

bool InputSteps::next(LogStep& out) {
  if (ahead_.empty() && !pull()) return false;
  out = std::move(ahead_.front());
  ahead_.pop_front();
  if (taken_ > 0 && !(out.timestamp > last_time_) && clock_.count++ == 0) {
    clock_.first_step = taken_;
    clock_.first_time = out.timestamp;
    clock_.time_before = last_time_;
  }
  last_time_ = out.timestamp;
  ++taken_;
  return true;
}

void InputSteps::warn_if_clock_faults() const {
  if (clock_.count == 0) return;
  std::fprintf(stderr,
               "hmt-slam: warning: the log's timestamps do not increase at %zu of its %zu "
               "scans (first at scan %zu: %.6f after %.6f); the outputs keep them as read, "
               "so compare trajectories by scan index, not by time\n",
               clock_.count, taken_, clock_.first_step, clock_.first_time, clock_.time_before);
}

}  // namespace hmt::pipeline

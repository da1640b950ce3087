// The steps of the input log a job uses, read from the log as they are
// needed: [input] first_step, max_steps and max_step_motion applied on the
// fly (InputOptions::select() is this, drained). A stream over the log's
// stream, so io::drain() and everything else that takes a LogStream takes it.
#pragma once

#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "hmt/common/sensor_data.h"
#include "hmt/io/log_stream.h"
#include "hmt/pipeline/metric_job.h"

namespace hmt::pipeline {

// Opens the input log (again): io::open_log() of [input] log, or a log in
// memory for tests.
using LogOpener = std::function<std::unique_ptr<io::LogStream>()>;

class InputSteps : public io::LogStream {
 public:
  InputSteps(std::unique_ptr<io::LogStream> stream, const InputOptions& input);

  // The step `ahead` places after the next one, read but not taken; nullptr
  // past the last. The steps peeked are held until taken.
  const LogStep* peek(size_t ahead = 0);
  // Takes the next step; false past the last. Throws InputError naming the
  // step (its index in the log) for odometry that moves more than
  // max_step_motion, and whatever the reader throws.
  bool next(LogStep& out) override;
  // How many steps have been taken.
  size_t taken() const { return taken_; }
  // How many steps there are, when the reader knows before the end.
  std::optional<size_t> total_steps() const override;
  // Roughly how much of the steps have been read, in [0, 1], for progress
  // when total_steps() is unknown: the share of the file read, or of
  // max_steps.
  double fraction_read() const override;

 private:
  // The next selected step from the stream into ahead_; false at the end.
  bool pull();

  std::unique_ptr<io::LogStream> stream_;
  InputOptions input_;
  std::deque<LogStep> ahead_;
  size_t pulled_ = 0;  // selected steps read from the stream
  size_t taken_ = 0;
  bool skipped_ = false;  // first_step steps dropped
};

}  // namespace hmt::pipeline

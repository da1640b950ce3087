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

class FrozenOdometryCheck;  // frozen_odometry.h
class OdometryTurnsCheck;   // odometry_turns.h

// Opens the input log (again): io::open_log() of [input] log, or a log in
// memory for tests.
using LogOpener = std::function<std::unique_ptr<io::LogStream>()>;

class InputSteps : public io::LogStream {
 public:
  // `check_odometry`: the odometry checked against the scans as the steps
  // are read (frozen_odometry.h, odometry_turns.h); off for a second
  // reading of a log the run has read already (read_steps_again).
  InputSteps(std::unique_ptr<io::LogStream> stream, const InputOptions& input,
             bool check_odometry = true);
  ~InputSteps() override;

  // The step `ahead` places after the next one, read but not taken; nullptr
  // past the last. The steps peeked are held until taken.
  const LogStep* peek(size_t ahead = 0);
  // Takes the next step; false past the last. Throws InputError naming the
  // step (its index in the log) for odometry that moves more than
  // max_step_motion, for odometry that stands still while the laser sees
  // the robot move or turns otherwise than the laser sees it turn (when
  // checked), and whatever the reader throws.
  bool next(LogStep& out) override;
  // How many steps have been taken.
  size_t taken() const { return taken_; }
  // The steps taken whose timestamp is not after the step before's: a clock
  // that repeats (csail's log rounds its times to 10 s), jumps back, or is
  // garbage. The filter does not use the times; the outputs keep them.
  struct ClockFaults {
    size_t count = 0;
    size_t first_step = 0;  // index among the steps taken, as trajectory.tum's lines
    double first_time = 0.0, time_before = 0.0;
  };
  const ClockFaults& clock_faults() const { return clock_; }
  // A warning on stderr when there are any: trajectories are then to be
  // compared by scan index, not by time.
  void warn_if_clock_faults() const;
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
  ClockFaults clock_;
  double last_time_ = 0.0;  // the last step taken's timestamp
  std::unique_ptr<FrozenOdometryCheck> frozen_;  // both null when not checked
  std::unique_ptr<OdometryTurnsCheck> turns_;
};

}  // namespace hmt::pipeline

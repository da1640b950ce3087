#include "rawlog_collector.h"

#include <cmath>
#include <stdexcept>

#include "hmt/common/error.h"
#include "rawlog_scan.h"

namespace hmt::io::detail {
namespace {

Pose2D to_pose(const Pose2DRecord& p) {
  return Pose2D(p.x, p.y, wrap_angle(p.phi));
}

bool finite(const Pose2D& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.theta);
}

}  // namespace

void RawlogCollector::check_clean_end(const GzInputStream& in) const {
  const std::string zerr = in.compression_error();
  if (!zerr.empty())
    throw InputError(prefix() + "is a damaged gzip file (zlib: " + zerr + ", after " +
                     std::to_string(entry_) + " entries)");
}

void RawlogCollector::unreadable_entry(GzInputStream& in, bool chosen_by_content,
                                       bool absurd_size) const {
  const std::string zerr = in.compression_error();
  if (!zerr.empty())
    throw InputError(prefix() + "is a damaged gzip file (zlib: " + zerr +
                     ", found while reading entry " + std::to_string(entry_) + ")");
  // Input left over: the object itself is wrong, and if it is the first,
  // the file is most likely not a rawlog at all.
  const bool cut_short = in.at_end();
  if (entry_ == 0 && !cut_short)
    throw InputError((chosen_by_content
                          ? "input log '" + path_ + "' is neither a CARMEN log nor an MRPT rawlog"
                          : prefix() + "is not an MRPT rawlog") +
                     " (its first object cannot be read)");
  throw InputError(prefix() + (cut_short ? "is truncated" : "is corrupt") + ": entry " +
                   std::to_string(entry_) + " cannot be read" +
                   (absurd_size ? " (absurd size)" : ""));
}

void RawlogCollector::not_an_entry(const std::string& class_name) const {
  throw InputError(prefix() + "entry " + std::to_string(entry_) + " is a " +
                   class_name +
                   ", not a rawlog entry (CSensoryFrame, CActionCollection "
                   "or CObservation)");
}

void RawlogCollector::empty_entry() const {
  throw InputError(prefix() + "entry " + std::to_string(entry_) +
                   " is an empty object");
}

void RawlogCollector::add_move(const MoveRecord& mv) {
  // The raw odometry reading is only filled in for odometry-based
  // estimates; otherwise (scan matching) the PDF's mean is the estimate.
  Pose2D inc;
  if (mv.method == MoveRecord::kOdometry) {
    inc = to_pose(mv.raw_increment);
  } else {
    if (!mv.has_pdf)
      throw InputError(prefix() + "entry " + std::to_string(entry_) +
                       " holds a robot movement without an estimate");
    inc = to_pose(mv.pdf_mean);
  }
  if (!finite(inc))
    throw InputError(prefix() + "entry " + std::to_string(entry_) +
                     " holds a non-finite odometry increment");
  if (source_ == Source::kReadings)
    throw InputError(prefix() + "entry " + std::to_string(entry_) +
                     " holds a robot movement (CActionRobotMovement2D), but " +
                     std::to_string(steps_made_) +
                     " scans before it took their odometry from CObservationOdometry "
                     "readings: a file must use one or the other");
  pending_increment_ = pending_increment_ + inc;
  if (source_ == Source::kUnknown) decide(Source::kMovements);
}

void RawlogCollector::add_scan(const ScanRecord& scan) {
  PendingScan p;
  try {
    p.scan = to_laser_scan(scan);
  } catch (const std::invalid_argument& e) {
    throw InputError(prefix() + "scan " + std::to_string(scans_read_) +
                     " (entry " + std::to_string(entry_) +
                     ") is unusable: " + e.what());
  }
  ++scans_read_;
  p.action_increment = pending_increment_;
  p.odometry = latest_odometry_;
  pending_increment_ = Pose2D();
  if (latest_odometry_) scan_after_reading_ = true;
  if (source_ == Source::kUnknown)
    held_.push_back(std::move(p));
  else
    make_step(p);
}

void RawlogCollector::add_odometry(const Pose2DRecord& odometry) {
  const Pose2D pose = to_pose(odometry);
  if (!finite(pose))
    throw InputError(prefix() + "entry " + std::to_string(entry_) +
                     " holds a non-finite odometry pose");
  latest_odometry_ = pose;
  if (!first_odometry_) first_odometry_ = pose;
  // A reading, a scan, a reading, and no movement so far: the
  // observations-only layout (rawlog_collector.h).
  if (source_ == Source::kUnknown && scan_after_reading_) decide(Source::kReadings);
}

void RawlogCollector::decide(Source source) {
  source_ = source;
  for (PendingScan& p : held_) make_step(p);
  held_.clear();
}

// Observations-only files: each scan takes the latest odometry reading
// before it in the file (no interpolation). File order rather than
// timestamps, because logs converted from other formats can carry rounded
// or non-monotonic clocks; MRPT's grabbers write observations in time order,
// so for them the two agree. Scans before the first odometry reading take
// that first reading (the robot has not been seen moving).
void RawlogCollector::make_step(PendingScan& s) {
  const bool movements = source_ == Source::kMovements;
  LogStep step;
  step.timestamp = s.scan.timestamp;
  step.scan = std::move(s.scan);
  const Pose2D odo = movements ? Pose2D() : s.odometry.value_or(*first_odometry_);
  if (steps_made_ > 0) {
    step.has_odometry = true;
    step.odometry_increment = movements ? s.action_increment : odo - previous_odometry_;
  }
  previous_odometry_ = odo;
  ++steps_made_;
  ready_.push_back(std::move(step));
}

bool RawlogCollector::next_step(LogStep& out) {
  if (ready_.empty()) return false;
  out = std::move(ready_.front());
  ready_.pop_front();
  return true;
}

void RawlogCollector::end_of_file(size_t entries) {
  if (scans_read_ == 0)
    throw InputError(prefix() + "holds no 2D laser scans (" +
                     std::to_string(entries) + " entries read)");
  if (source_ != Source::kUnknown) return;
  if (!first_odometry_)
    throw InputError(prefix() + "holds " + std::to_string(scans_read_) +
                     " laser scans but no odometry (neither "
                     "CActionRobotMovement2D nor CObservationOdometry)");
  decide(Source::kReadings);
}

}  // namespace hmt::io::detail

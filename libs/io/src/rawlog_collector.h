// Turns the rawlog's scans, odometry readings and robot movements, in file
// order, into the internal stream. Both odometry sources are kept until the
// end, since which one a file uses is only known then. Shared by the native
// reader and the MRPT plugin, so that both give the same log for the same
// file.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "gz_stream.h"
#include "hmt/common/sensor_data.h"
#include "rawlog_records.h"

namespace hmt::io::detail {

class RawlogCollector {
 public:
  explicit RawlogCollector(const std::string& path) : path_(path) {}

  // The index of the top-level entry being read, for messages.
  void set_entry(size_t entry) { entry_ = entry; }

  void add_scan(const ScanRecord& scan);
  // A CObservationOdometry: the absolute dead-reckoning pose.
  void add_odometry(const Pose2DRecord& pose);
  // A CActionRobotMovement2D: an increment since the previous one.
  void add_move(const MoveRecord& move);

  // The reader found `in` at its end before the next entry: returns if the
  // end is clean, throws the InputError for a damaged gzip stream.
  void check_clean_end(const GzInputStream& in) const;
  // Throws the InputError for the entry being read when it cannot be read
  // (the clean end was handled by check_clean_end): damaged gzip; not a
  // rawlog at all (the first entry, input left over; `chosen_by_content`:
  // the log's type was guessed from its content); truncated; corrupt.
  // `absurd_size`: the object claimed more memory than could be allocated.
  [[noreturn]] void unreadable_entry(GzInputStream& in, bool chosen_by_content,
                                     bool absurd_size = false) const;

  // Throws the InputError for a top-level object that is no rawlog entry.
  [[noreturn]] void not_an_entry(const std::string& class_name) const;
  // ... and for a null one.
  [[noreturn]] void empty_entry() const;

  // The log (the scans are moved into it); throws InputError if it holds no
  // scans, or scans but no odometry. `entries` is how many top-level
  // objects were read.
  hmt::Log finish(size_t entries);

 private:
  struct PendingScan {
    hmt::LaserScan scan;
    Pose2D action_increment;         // composed actions since last scan
    std::optional<Pose2D> odometry;  // latest CObservationOdometry
  };

  std::string prefix() const { return "rawlog '" + path_ + "' "; }

  std::string path_;
  size_t entry_ = 0;
  std::vector<PendingScan> scans_;
  Pose2D pending_increment_;
  bool any_action_ = false;
  std::optional<Pose2D> latest_odometry_;
  std::optional<Pose2D> first_odometry_;
};

}  // namespace hmt::io::detail

// Turns the rawlog's scans, odometry readings and robot movements, in file
// order, into the internal stream, step by step. Shared by the native
// reader and the MRPT plugin, which drive it alike (the next entry is read
// when no step is final), so that both give the same steps for the same
// file, and the same errors at the same points.
//
// The odometry source: robot movements (CActionRobotMovement2D) if the file
// holds any, else odometry readings (CObservationOdometry). A scan's step is
// final once the source is known, and scans are held back until then:
//  - the first robot movement decides for movements;
//  - an odometry reading that comes after a scan which itself came after an
//    odometry reading, with no robot movement before, decides for readings
//    (two readings with a scan between them: the observations-only layout,
//    so at most the scans before the second reading are held back);
//  - the end of the file decides what is still open (readings if there were
//    any, else the "no odometry" error).
// A robot movement after the decision for readings is an InputError (the
// file mixes the two layouts). The reader used to decide at the end of the
// file, for movements whenever any appeared: on every file that does not mix
// the layouts that way the steps are the same.
#pragma once

#include <deque>
#include <optional>
#include <string>

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

  // The next step that is final, into `out`; false if none is (yet).
  bool next_step(LogStep& out);
  // The file ended after `entries` top-level objects: the scans held back
  // become final. Throws InputError if the file held no scans, or scans but
  // no odometry.
  void end_of_file(size_t entries);

 private:
  enum class Source { kUnknown, kMovements, kReadings };
  struct PendingScan {
    hmt::LaserScan scan;
    Pose2D action_increment;         // composed actions since last scan
    std::optional<Pose2D> odometry;  // latest CObservationOdometry
  };

  std::string prefix() const { return "rawlog '" + path_ + "' "; }
  // Fixes the source; the scans held back become final.
  void decide(Source source);
  void make_step(PendingScan& scan);

  std::string path_;
  size_t entry_ = 0;
  Source source_ = Source::kUnknown;
  size_t scans_read_ = 0;
  size_t steps_made_ = 0;
  std::deque<PendingScan> held_;  // while the source is unknown
  std::deque<LogStep> ready_;     // final, not taken yet
  Pose2D pending_increment_;
  Pose2D previous_odometry_;      // of the last step made (readings)
  bool scan_after_reading_ = false;
  std::optional<Pose2D> latest_odometry_;
  std::optional<Pose2D> first_odometry_;
};

}  // namespace hmt::io::detail

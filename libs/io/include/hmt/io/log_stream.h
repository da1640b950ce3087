// Reading a log step by step, so that a long log need not fit in memory.
//
// open_log() picks the reader as read_log() does (log_reader.h) and hands
// out the same steps, in order; read_log() is open_log() drained, so each
// format has one reader. What each reader holds while it streams:
//  - MRPT rawlog, read natively: one entry at a time; scans are held back
//    only until the file's odometry source is known (rawlog.h);
//  - MRPT rawlog holding a class only MRPT reads (images, GPS...): the same,
//    through the MRPT plugin (src/mrpt_fallback.h), which reads the file
//    again from its start when the native reader meets that class (the
//    steps already handed out are skipped, not held), and one entry's MRPT
//    objects at a time;
//  - CARMEN: one line at a time, in two passes over the file (the
//    no-return threshold, the dead beams and FLASER-or-ROBOTLASER1 are
//    decided over all its scans in the first, carmen.h);
//  - ROS bag: one scan at a time, in two passes through the plugin (the
//    odometry at each scan's stamp is interpolated between messages that
//    may come later in the file, so the first reads the odometry and
//    transforms whole, and of the scans only what the choices need,
//    rosbag.h).
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "hmt/common/sensor_data.h"
#include "hmt/io/rosbag.h"

namespace hmt::io {

class LogStream {
 public:
  virtual ~LogStream() = default;

  // The next step into `out`; false at the clean end of the log. Throws
  // hmt::InputError, as read_log() would, when the reader reaches damage or
  // finds at the end that the log is unusable (no scans, no odometry): steps
  // handed out before that were good.
  virtual bool next(LogStep& out) = 0;

  // The file, as read_log() names it in Log::source.
  const std::string& source() const { return source_; }

  // How much of the file has been read, in [0, 1], for progress reports
  // (bytes of the file, compressed if it is; a bag's scan messages; 1 for a
  // log read whole).
  virtual double fraction_read() const = 0;

  // How many steps the log holds, when that is known before the end (a log
  // read whole, or a CARMEN log or a bag after its first pass).
  virtual std::optional<size_t> total_steps() const { return std::nullopt; }

 protected:
  explicit LogStream(std::string source) : source_(std::move(source)) {}

 private:
  std::string source_;
};

// Opens `path` (any format read_log() reads); throws hmt::InputError as
// read_log() does for a missing, empty or unrecognised file. The first pass
// of a CARMEN log or a bag is made here, so their errors are thrown here.
std::unique_ptr<LogStream> open_log(const std::string& path, const BagOptions& bag = {});

// Every step left in `stream`, as a log named after its source.
hmt::Log drain(LogStream& stream);

// A log already in memory as a stream (what the whole-file readers return;
// tests feed jobs with it).
std::unique_ptr<LogStream> stream_of(hmt::Log log);

}  // namespace hmt::io

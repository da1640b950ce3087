// The MRPT plugin: reads a rawlog with MRPT's own deserializers, entry by
// entry as the steps are asked for, for files holding classes the native
// reader does not know (images, GPS, 3D scans... in multi-sensor logs).
// Loaded with dlopen by mrpt_fallback.cc, so that MRPT is only mapped into
// processes that need it.
//
// The objects are converted to the same records the native reader makes and
// collected by the same RawlogCollector, driven the same way (an entry is
// read when no step is final), so both give the same steps and the same
// errors at the same points, and hold the same: one entry, and the scans
// that wait for the odometry source.
#include <climits>
#include <new>
#include <stdexcept>
#include <string>

#include <mrpt/io/CStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include "gz_stream.h"
#include "hmt/common/error.h"
#include "mrpt_plugin_abi.h"
#include "rawlog_collector.h"
#include "rawlog_records.h"

namespace hmt::io::detail {
namespace {

using mrpt::obs::CActionCollection;
using mrpt::obs::CActionRobotMovement2D;
using mrpt::obs::CObservation;
using mrpt::obs::CObservation2DRangeScan;
using mrpt::obs::CObservationOdometry;
using mrpt::obs::CRawlog;
using mrpt::obs::CSensoryFrame;
using mrpt::serialization::CSerializable;

// GzInputStream as an MRPT stream.
class MrptGzStream : public mrpt::io::CStream {
 public:
  explicit MrptGzStream(GzInputStream& in) : in_(in) {}

  // All `count` bytes, or 0: MRPT's readers of plain values ignore short
  // reads, so a partial read must look like a failure to them.
  size_t Read(void* buffer, size_t count) override {
    return in_.read(buffer, count) == count ? count : 0;
  }
  size_t Write(const void*, size_t) override {
    throw std::logic_error("MrptGzStream is read-only");
  }
  uint64_t Seek(int64_t, TSeekOrigin) override {
    throw std::logic_error("MrptGzStream cannot seek");
  }
  // Unknown before the whole file is decompressed; MRPT only uses it for
  // progress reports.
  uint64_t getTotalBytesCount() const override { return 0; }
  uint64_t getPosition() const override { return in_.position(); }
  std::string getStreamDescription() const override {
    return "input log '" + in_.path() + "'";
  }

 private:
  GzInputStream& in_;
};

Pose2DRecord record(const mrpt::poses::CPose2D& p) {
  return Pose2DRecord{p.x(), p.y(), p.phi()};
}

ScanRecord record(const CObservation2DRangeScan& s) {
  ScanRecord r;
  r.aperture = s.aperture;
  r.right_to_left = s.rightToLeft;
  r.max_range = s.maxRange;
  r.sensor_pose.x = s.sensorPose.x();
  r.sensor_pose.y = s.sensorPose.y();
  r.sensor_pose.z = s.sensorPose.z();
  const auto rot = s.sensorPose.getRotationMatrix();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.sensor_pose.rot[i][j] = rot(i, j);
  const size_t n = s.getScanSize();
  r.ranges.resize(n);
  r.valid.resize(n);
  for (size_t i = 0; i < n; ++i) {
    r.ranges[i] = s.getScanRange(i);
    r.valid[i] = s.getScanRangeValidity(i) ? 1 : 0;
  }
  r.timestamp = s.timestamp.time_since_epoch().count();
  return r;
}

MoveRecord record(const CActionRobotMovement2D& mv) {
  MoveRecord r;
  r.method = static_cast<int32_t>(mv.estimationMethod);
  r.raw_increment = record(mv.rawOdometryIncrementReading);
  // Only estimates other than odometry use the PDF (and for odometry the
  // Thrun model's PDF is a particle set whose mean costs time).
  if (r.method != MoveRecord::kOdometry && mv.poseChange.get_ptr()) {
    r.has_pdf = true;
    r.pdf_mean = record(mv.poseChange->getMeanVal());
  }
  return r;
}

void add_observation(const CObservation::Ptr& o, RawlogCollector& collector) {
  if (auto scan = std::dynamic_pointer_cast<CObservation2DRangeScan>(o))
    collector.add_scan(record(*scan));
  else if (auto odo = std::dynamic_pointer_cast<CObservationOdometry>(o))
    collector.add_odometry(record(odo->odometry));
  // Any other observation type is of no use here.
}

void add_entry(const CSerializable::Ptr& obj, RawlogCollector& collector,
               bool inside_rawlog) {
  if (!obj) collector.empty_entry();
  if (auto sf = std::dynamic_pointer_cast<CSensoryFrame>(obj)) {
    for (const auto& o : *sf) add_observation(o, collector);
  } else if (auto acts = std::dynamic_pointer_cast<CActionCollection>(obj)) {
    for (const auto& a : *acts) {
      // Other actions (e.g. 3D movements) are not used.
      if (auto mv = std::dynamic_pointer_cast<CActionRobotMovement2D>(
              a.get_ptr()))
        collector.add_move(record(*mv));
    }
  } else if (auto o = std::dynamic_pointer_cast<CObservation>(obj)) {
    add_observation(o, collector);
  } else if (auto raw = std::dynamic_pointer_cast<CRawlog>(obj)) {
    // Very old files hold a whole CRawlog object instead of a sequence.
    if (inside_rawlog) collector.not_an_entry(obj->GetRuntimeClass()->className);
    for (size_t i = 0; i < raw->size(); ++i)
      add_entry(raw->getAsGeneric(i), collector, true);
  } else {
    collector.not_an_entry(obj->GetRuntimeClass()->className);
  }
}

}  // namespace

// One open rawlog: the file, MRPT's archive over it, and the collector.
struct MrptRawlogCursor {
  MrptRawlogCursor(const std::string& path, bool by_content)
      : chosen_by_content(by_content), in(path), stream(in), archive(stream),
        collector(path) {}

  bool next(LogStep& out) {
    while (!collector.next_step(out)) {
      if (ended) return false;
      read_entry();
    }
    return true;
  }

  // One top-level object, or the end of the file.
  void read_entry() {
    collector.set_entry(entry);
    if (in.at_end()) {
      collector.check_clean_end(in);
      collector.end_of_file(entry);
      ended = true;
      return;
    }
    CSerializable::Ptr obj;
    try {
      obj = archive.ReadObject();
    } catch (const std::exception& e) {
      // MRPT reports a clean end and a cut inside an object alike; at_end()
      // above already handled the clean end, so this is damage.
      collector.unreadable_entry(in, chosen_by_content,
                                 dynamic_cast<const std::bad_alloc*>(&e) != nullptr);
    }
    add_entry(obj, collector, false);
    ++entry;
  }

  const bool chosen_by_content;
  GzInputStream in;
  MrptGzStream stream;  // reads `in`
  mrpt::serialization::CArchiveStreamBase<MrptGzStream> archive;  // reads `stream`
  RawlogCollector collector;
  size_t entry = 0;
  bool ended = false;
};

namespace {

PluginStatus open_rawlog(const char* path, bool chosen_by_content, MrptRawlogCursor** cursor,
                         std::string* error) {
  return plugin_status_of(error,
                          [&] { *cursor = new MrptRawlogCursor(path, chosen_by_content); });
}

PluginStatus next_step(MrptRawlogCursor* cursor, LogStep* step, bool* got, std::string* error) {
  return plugin_status_of(error, [&] { *got = cursor->next(*step); });
}

uint64_t file_offset(const MrptRawlogCursor* cursor) { return cursor->in.file_offset(); }

void close_rawlog(MrptRawlogCursor* cursor) { delete cursor; }

}  // namespace
}  // namespace hmt::io::detail

extern "C" __attribute__((visibility("default")))
const hmt::io::detail::MrptRawlogPlugin* hmt_io_mrpt_rawlog_plugin_v2() {
  using namespace hmt::io::detail;
  static const MrptRawlogPlugin plugin{&open_rawlog, &next_step, &file_offset, &close_rawlog};
  return &plugin;
}

// The MRPT plugin: reads a whole rawlog with MRPT's own deserializers, for
// files holding classes the native reader does not know (images, GPS, 3D
// scans... in multi-sensor logs). Loaded with dlopen by mrpt_fallback.cc, so
// that MRPT is only mapped into processes that need it.
//
// The objects are converted to the same records the native reader makes and
// collected by the same RawlogCollector, so both give the same log.
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

hmt::Log read_rawlog(const std::string& path, bool chosen_by_content) {
  GzInputStream in(path);
  MrptGzStream stream(in);
  auto archive = mrpt::serialization::archiveFrom(stream);
  RawlogCollector collector(path);
  size_t entry = 0;
  for (;; ++entry) {
    collector.set_entry(entry);
    if (in.at_end()) {
      collector.check_clean_end(in);
      break;
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
  }
  return collector.finish(entry);
}

}  // namespace
}  // namespace hmt::io::detail

extern "C" __attribute__((visibility("default")))
hmt::io::detail::MrptReadStatus hmt_io_mrpt_read_rawlog_v1(
    const char* path, bool chosen_by_content, hmt::Log* log,
    std::string* error) {
  using hmt::io::detail::MrptReadStatus;
  try {
    *log = hmt::io::detail::read_rawlog(path, chosen_by_content);
    return MrptReadStatus::kOk;
  } catch (const hmt::InputError& e) {
    *error = e.what();
    return MrptReadStatus::kInputError;
  } catch (const std::exception& e) {
    *error = e.what();
    return MrptReadStatus::kFailure;
  }
}

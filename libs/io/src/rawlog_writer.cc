// Writes rawlogs byte for byte as MRPT 2.5.8 writes the same objects (same
// class names, versions and default field values), so that MRPT's tools
// (rbpf-slam, RawLogViewer) read them as their own; the tests compare the
// bytes with MRPT's.
#include <functional>
#include <stdexcept>
#include <string>

#include "gz_stream.h"
#include "hmt/common/error.h"
#include "hmt/common/files.h"
#include "hmt/io/log_stream.h"
#include "hmt/io/rawlog.h"
#include "mrpt_archive.h"
#include "rawlog_scan.h"

namespace hmt::io {
namespace {

using detail::ArchiveWriter;
using detail::Pose2DRecord;
using detail::Pose3DRecord;
using detail::ScanRecord;

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() &&
         s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

void write_pose2d(ArchiveWriter& out, const Pose2D& p) {
  const Pose2DRecord r = detail::mrpt_pose2d(p.x, p.y, p.theta);
  out.begin_object("mrpt::poses::CPose2D", 1);
  out.f64(r.x);
  out.f64(r.y);
  out.f64(r.phi);
  out.end_object();
}

void write_pose3d(ArchiveWriter& out, const Pose3DRecord& p) {
  out.begin_object("mrpt::poses::CPose3D", 3);
  out.f64(p.x);
  out.f64(p.y);
  out.f64(p.z);
  for (const auto& row : p.rot)
    for (double v : row) out.f64(v);
  out.end_object();
}

void write_scan(ArchiveWriter& out, const ScanRecord& s) {
  const auto n = static_cast<uint32_t>(s.ranges.size());
  out.begin_object("mrpt::obs::CObservation2DRangeScan", 7);
  out.f32(s.aperture);
  out.boolean(s.right_to_left);
  out.f32(s.max_range);
  write_pose3d(out, s.sensor_pose);
  out.u32(n);
  out.bytes(s.ranges.data(), n * sizeof(float));
  out.bytes(s.valid.data(), n);
  out.f32(0.01f);  // stdError (MRPT's default)
  out.u64(static_cast<uint64_t>(s.timestamp));
  out.f32(0.0f);   // beamAperture
  out.string("LASER");
  out.f64(0.0);    // deltaPitch
  out.boolean(false);  // no intensities
  out.end_object();
}

// A CActionCollection holding one CActionRobotMovement2D computed from the
// odometry increment with the default motion model options (Gaussian).
void write_actions(ArchiveWriter& out, const Pose2D& inc, int64_t timestamp) {
  out.begin_object("mrpt::obs::CActionCollection", 0);
  out.u32(1);
  out.begin_object("mrpt::obs::CActionRobotMovement2D", 7);
  out.u32(0);  // emOdometry: the raw reading and the model, not the PDF
  write_pose2d(out, inc);
  out.u32(0);  // mmGaussian
  // TMotionModelOptions' defaults as MRPT writes them (floats).
  for (float v : {0x1.47ae14p-7f, 0x1.d55df6p-5f, 0x1.1df46ap-6f,
                  0x1.99999ap-5f, 0x1.47ae14p-7f, 0x1.c98710p-9f})
    out.f32(v);  // Gaussian a1 a2 a3 a4 minStdXY minStdPHI
  out.u32(300);  // Thrun model: particle count, then its parameters
  for (float v : {0x1.99999ap-5f, 0x1.1df46ap-4f, 0x1.47ae14p-7f,
                  0x1.777e5cp-8f, 0x1.0624dep-10f, 0x1.c98712p-11f})
    out.f32(v);
  out.boolean(false);  // hasVelocities
  out.boolean(false);  // hasEncodersInfo
  out.u64(static_cast<uint64_t>(timestamp));
  out.end_object();
  out.end_object();
}

void write_frame(ArchiveWriter& out, const ScanRecord& scan) {
  out.begin_object("mrpt::obs::CSensoryFrame", 2);
  out.u32(1);
  write_scan(out, scan);
  out.end_object();
}

void write_odometry(ArchiveWriter& out, const Pose2D& pose, int64_t timestamp) {
  out.begin_object("mrpt::obs::CObservationOdometry", 2);
  write_pose2d(out, pose);
  out.string("ODOMETRY");
  out.u64(static_cast<uint64_t>(timestamp));
  out.boolean(false);  // hasEncodersInfo
  out.boolean(false);  // hasVelocities
  out.end_object();
}

// Writes the steps `next` hands out (nullptr after the last); returns how
// many.
size_t write_steps(const std::function<const LogStep*()>& next, RawlogFormat format,
                   ArchiveWriter& out) {
  Pose2D odometry;  // accumulated, for the observations-only layout
  size_t k = 0;
  for (const LogStep* p = next(); p && out.ok(); p = next(), ++k) {
    const LogStep& step = *p;
    ScanRecord scan;
    try {
      scan = detail::to_scan_record(step.scan, step.timestamp);
    } catch (const std::invalid_argument& e) {
      throw OutputError("cannot write step " + std::to_string(k) +
                        " as a rawlog scan: " + e.what());
    }
    const Pose2D inc = step.has_odometry ? step.odometry_increment : Pose2D();
    if (format == RawlogFormat::kActionsSensoryFrames) {
      // Like MRPT's own logs, the first sensory frame has no action before it.
      if (k > 0) write_actions(out, inc, scan.timestamp);
      write_frame(out, scan);
    } else {
      if (k > 0) odometry = odometry + inc;
      write_odometry(out, odometry, scan.timestamp);
      write_scan(out, scan);
    }
  }
  return k;
}

size_t write_steps_to(const std::string& path, RawlogFormat format,
                      const std::function<const LogStep*()>& next) {
  const bool gzip = ends_with(path, ".gz");
  size_t n = 0;
  write_file_atomically(path, [&](std::ostream& os) {
    detail::GzOutputStream stream(os, gzip);
    ArchiveWriter archive(stream);
    n = write_steps(next, format, archive);
    if (!archive.ok() || !stream.finish())
      throw OutputError("failed writing rawlog '" + path + "'");
  });
  return n;
}

}  // namespace

void write_rawlog(const hmt::Log& log, const std::string& path,
                  RawlogFormat format) {
  size_t k = 0;
  write_steps_to(path, format, [&]() -> const LogStep* {
    return k < log.steps.size() ? &log.steps[k++] : nullptr;
  });
}

size_t write_rawlog(LogStream& log, const std::string& path, RawlogFormat format) {
  LogStep step;
  return write_steps_to(path, format,
                        [&]() -> const LogStep* { return log.next(step) ? &step : nullptr; });
}

}  // namespace hmt::io

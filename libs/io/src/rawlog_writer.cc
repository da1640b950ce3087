#include <cmath>
#include <stdexcept>
#include <string>

#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include "gz_stream.h"
#include "hmt/common/error.h"
#include "hmt/common/files.h"
#include "hmt/io/rawlog.h"
#include "mrpt_scan.h"

namespace hmt::io {
namespace {

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() &&
         s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

mrpt::poses::CPose2D to_mrpt(const Pose2D& p) {
  return mrpt::poses::CPose2D(p.x, p.y, p.theta);
}

void write_steps(const hmt::Log& log, RawlogFormat format,
                 mrpt::serialization::CArchive& out) {
  using namespace mrpt::obs;
  Pose2D odometry;  // accumulated, for the observations-only layout
  for (size_t k = 0; k < log.steps.size(); ++k) {
    const LogStep& step = log.steps[k];
    auto scan = CObservation2DRangeScan::Create();
    try {
      detail::to_mrpt_scan(step.scan, step.timestamp, *scan);
    } catch (const std::invalid_argument& e) {
      throw OutputError("cannot write step " + std::to_string(k) +
                        " as a rawlog scan: " + e.what());
    }
    const Pose2D inc = step.has_odometry ? step.odometry_increment : Pose2D();
    if (format == RawlogFormat::kActionsSensoryFrames) {
      // Like MRPT's own logs, the first sensory frame has no action before it.
      if (k > 0) {
        CActionRobotMovement2D move;
        move.computeFromOdometry(
            to_mrpt(inc), CActionRobotMovement2D::TMotionModelOptions());
        move.timestamp = scan->timestamp;
        CActionCollection actions;
        actions.insert(move);
        out << actions;
      }
      CSensoryFrame frame;
      frame.insert(scan);
      out << frame;
    } else {
      if (k > 0) odometry = odometry + inc;
      CObservationOdometry odo;
      odo.odometry = to_mrpt(odometry);
      odo.timestamp = scan->timestamp;
      odo.sensorLabel = "ODOMETRY";
      out << odo;
      out << *scan;
    }
  }
}

}  // namespace

void write_rawlog(const hmt::Log& log, const std::string& path,
                  RawlogFormat format) {
  const bool gzip = ends_with(path, ".gz");
  write_file_atomically(path, [&](std::ostream& os) {
    detail::OstreamOutputStream stream(os, gzip);
    auto archive = mrpt::serialization::archiveFrom(stream);
    try {
      write_steps(log, format, archive);
    } catch (const hmt::Error&) {
      throw;
    } catch (const std::exception&) {
      // MRPT only says "Cannot write bytes to stream!" with a stack trace.
      throw OutputError("failed writing rawlog '" + path + "'");
    }
    if (!stream.finish())
      throw OutputError("failed writing rawlog '" + path + "'");
  });
}

}  // namespace hmt::io

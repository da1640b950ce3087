// Building rawlogs with MRPT itself, for the reader tests (reference files,
// malformed files) and for comparing the native writer's bytes with MRPT's.
#pragma once

#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <initializer_list>
#include <string>
#include <vector>

#include "hmt/common/sensor_data.h"
#include "hmt/io/rawlog.h"
#include "rawlog_scan.h"

namespace hmt::io::testing_util {

// A 5-beam, 180-degree scan with readings 1..5 m.
inline mrpt::obs::CObservation2DRangeScan::Ptr make_scan(double t) {
  auto s = mrpt::obs::CObservation2DRangeScan::Create();
  s->resizeScan(5);
  for (size_t i = 0; i < 5; ++i) {
    s->setScanRange(i, static_cast<float>(i + 1));
    s->setScanRangeValidity(i, true);
  }
  s->aperture = static_cast<float>(M_PI);
  s->rightToLeft = true;
  s->maxRange = 30.0f;
  s->timestamp = mrpt::Clock::fromDouble(t);
  s->sensorLabel = "LASER";
  return s;
}

inline mrpt::obs::CObservationOdometry::Ptr make_odometry(double t, double x,
                                                           double y,
                                                           double phi) {
  auto o = mrpt::obs::CObservationOdometry::Create();
  o->odometry = mrpt::poses::CPose2D(x, y, phi);
  o->timestamp = mrpt::Clock::fromDouble(t);
  return o;
}

// An action holding the robot movement (x, y, phi), from odometry or, with
// `scan_matching`, as an estimate whose PDF alone holds it.
inline mrpt::obs::CActionCollection::Ptr make_action(double x, double y, double phi,
                                                     bool scan_matching = false) {
  mrpt::obs::CActionRobotMovement2D mv;
  mv.computeFromOdometry(mrpt::poses::CPose2D(x, y, phi), {});
  if (scan_matching) {
    mv.estimationMethod = mrpt::obs::CActionRobotMovement2D::emScan2DMatching;
    mv.rawOdometryIncrementReading = mrpt::poses::CPose2D(0, 0, 0);
  }
  auto acts = mrpt::obs::CActionCollection::Create();
  acts->insert(mv);
  return acts;
}

inline mrpt::obs::CSensoryFrame::Ptr make_frame(
    std::initializer_list<mrpt::obs::CObservation::Ptr> obs) {
  auto sf = mrpt::obs::CSensoryFrame::Create();
  for (const auto& o : obs) sf->insert(o);
  return sf;
}

inline void write_objects(
    const std::string& path,
    const std::vector<mrpt::serialization::CSerializable::Ptr>& objs) {
  mrpt::io::CFileOutputStream f(path);
  auto ar = mrpt::serialization::archiveFrom(f);
  for (const auto& o : objs) ar << *o;
}

// The scan MRPT itself would be given for `in` (what the writer did when it
// wrote through MRPT).
inline mrpt::obs::CObservation2DRangeScan::Ptr mrpt_scan(
    const hmt::LaserScan& in, double timestamp) {
  const size_t n = in.size();
  const double inc = in.angle_increment;
  const double aperture = std::abs(inc) * double(n - 1);
  const bool right_to_left = inc >= 0.0;
  const double centre = right_to_left ? in.angle_min + aperture / 2.0
                                      : in.angle_min - aperture / 2.0;
  auto out = mrpt::obs::CObservation2DRangeScan::Create();
  out->resizeScan(n);
  for (size_t i = 0; i < n; ++i) {
    out->setScanRange(i, in.ranges[i]);
    out->setScanRangeValidity(i, in.valid[i] != 0);
  }
  out->aperture = static_cast<float>(aperture);
  out->rightToLeft = right_to_left;
  out->maxRange = in.max_range;
  out->sensorPose = mrpt::poses::CPose3D(
      in.sensor_pose.x, in.sensor_pose.y, 0.0,
      wrap_angle(in.sensor_pose.theta + centre), 0.0, 0.0);
  out->sensorLabel = "LASER";
  out->timestamp = mrpt::Clock::time_point(
      mrpt::Clock::duration(detail::to_mrpt_ticks(timestamp)));
  return out;
}

// `log` written by MRPT, in the layout write_rawlog() documents (plain).
inline void write_rawlog_with_mrpt(const hmt::Log& log, const std::string& path,
                                   RawlogFormat format) {
  using namespace mrpt::obs;
  mrpt::io::CFileOutputStream f(path);
  auto out = mrpt::serialization::archiveFrom(f);
  Pose2D odometry;
  for (size_t k = 0; k < log.steps.size(); ++k) {
    const LogStep& step = log.steps[k];
    auto scan = mrpt_scan(step.scan, step.timestamp);
    const Pose2D inc = step.has_odometry ? step.odometry_increment : Pose2D();
    if (format == RawlogFormat::kActionsSensoryFrames) {
      if (k > 0) {
        CActionRobotMovement2D move;
        move.computeFromOdometry(mrpt::poses::CPose2D(inc.x, inc.y, inc.theta),
                                 CActionRobotMovement2D::TMotionModelOptions());
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
      odo.odometry = mrpt::poses::CPose2D(odometry.x, odometry.y, odometry.theta);
      odo.timestamp = scan->timestamp;
      odo.sensorLabel = "ODOMETRY";
      out << odo;
      out << *scan;
    }
  }
}

}  // namespace hmt::io::testing_util

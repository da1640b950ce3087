// Building small rawlogs with MRPT itself, for the reader tests.
#pragma once

#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/serialization/CArchive.h>

#include <string>
#include <vector>

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

inline void write_objects(
    const std::string& path,
    const std::vector<mrpt::serialization::CSerializable::Ptr>& objs) {
  mrpt::io::CFileOutputStream f(path);
  auto ar = mrpt::serialization::archiveFrom(f);
  for (const auto& o : objs) ar << *o;
}

}  // namespace hmt::io::testing_util

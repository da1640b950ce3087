// Conversions between MRPT's scan / time representation (rawlog_records.h)
// and the internal one.
#pragma once

#include <cstdint>

#include "hmt/common/sensor_data.h"
#include "rawlog_records.h"

namespace hmt::io::detail {

// mrpt::Clock counts 100 ns ticks since 1601; MRPT's Clock::fromDouble()
// truncates and wraps for times before 1970 (some CARMEN logs start at
// t < 0), so the conversion is done here, rounding to the nearest tick.
// Throws std::invalid_argument for a non-finite time or one before 1601.
int64_t to_mrpt_ticks(double seconds_since_epoch);
// 0.0 for MRPT's "invalid" time (0 ticks).
double from_mrpt_ticks(int64_t ticks);
// mrpt::Clock::now() (the system clock), the time MRPT gives an observation
// that does not store one.
int64_t mrpt_now_ticks();

// Scan record -> LaserScan (see rawlog.h for the conventions). Throws
// std::invalid_argument with the reason (beam index and value) for a scan
// without beams, a NaN or negative reading, an unusable maxRange, an
// aperture outside [0, 2 pi] or a non-finite sensor pose.
hmt::LaserScan to_laser_scan(const ScanRecord& in);

// LaserScan -> scan record, keeping each beam's direction in the robot frame
// (see rawlog.h). Throws std::invalid_argument for a scan without beams or
// with as many validity flags as ranges, or a time MRPT cannot hold.
ScanRecord to_scan_record(const hmt::LaserScan& in, double timestamp);

// What MRPT's constructors store, bit for bit, so that written files are
// the ones MRPT itself would write:
//  - mrpt::math::wrapToPi(), which CPose2D(x, y, phi) applies to phi;
//  - CPose3D(x, y, z, yaw, pitch, roll): angles through wrapToPi(), then the
//    rotation matrix from them.
double mrpt_wrap_to_pi(double angle);
Pose2DRecord mrpt_pose2d(double x, double y, double phi);
Pose3DRecord mrpt_pose3d(double x, double y, double z, double yaw,
                         double pitch, double roll);

}  // namespace hmt::io::detail

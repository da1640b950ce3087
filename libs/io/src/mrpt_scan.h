// Conversions between MRPT's scan / time types and the internal ones.
#pragma once

#include <string>

#include <mrpt/core/Clock.h>
#include <mrpt/obs/CObservation2DRangeScan.h>

#include "hmt/common/sensor_data.h"

namespace hmt::io::detail {

// mrpt::Clock counts 100 ns ticks since 1601; Clock::fromDouble() truncates
// and wraps for times before 1970 (some CARMEN logs start at t < 0), so the
// conversion is done here, rounding to the nearest tick. Throws
// std::invalid_argument for a non-finite time or one before 1601.
mrpt::Clock::time_point to_mrpt_time(double seconds_since_epoch);
// 0.0 for MRPT's "invalid" (default-constructed) time point.
double from_mrpt_time(mrpt::Clock::time_point t);

// MRPT scan -> LaserScan (see rawlog.h for the conventions). Throws
// std::invalid_argument with the reason (beam index and value) for a scan
// without beams, a NaN or negative reading, or an unusable maxRange.
hmt::LaserScan from_mrpt_scan(const mrpt::obs::CObservation2DRangeScan& in);

// LaserScan -> MRPT scan, keeping each beam's direction in the robot frame.
void to_mrpt_scan(const hmt::LaserScan& in, double timestamp,
                  mrpt::obs::CObservation2DRangeScan& out);

}  // namespace hmt::io::detail

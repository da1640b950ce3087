// CARMEN text logs (plain or gzip) -> the internal stream.
//
// One step per FLASER line:
//   FLASER n r1..rn x y theta odom_x odom_y odom_theta timestamp host logger_ts
// (ROBOTLASER1 lines are used instead only in logs without any FLASER line.)
// The odometry is odom_x odom_y odom_theta; the timestamp is the first of the
// two, kept as it is (some logs' clocks are rounded or broken: the step order
// is the line order). ODOM, TRUEPOS, RAWLASER*, other PARAMs, comments (#)
// and other messages are ignored.
//
// Beam geometry (FLASER carries none): beam i points at -90 deg + i * res in
// the sensor frame, res = 1 deg for 180 or 181 beams, 0.5 deg for 360 or 361
// beams, and for any other count 180 deg / (n - 1) (first beam at -90 deg,
// last at +90 deg); unless the log's PARAMs say otherwise:
// `laser_front_laser_resolution` (degrees) or `laser_front_laser_fov`
// (radians up to 2 pi, else degrees) of a span other than 180 deg (to within
// a step) give the step and a span centred on the heading (a 270 deg laser
// of 1081 beams: -135 deg + i * 0.25 deg); a span beyond a full turn is an
// InputError. The sensor sits at (robot_frontlaser_offset, 0, 0) in
// the robot frame, from `PARAM robot_frontlaser_offset X`, else at the origin.
//
// No-return readings: a CARMEN log writes "no return" as the sensor's
// maximum value, which recurs thousands of times but jitters by up to
// ~0.15 m between logs and within one (edmonton: 51.09-51.16, acapulco:
// 51.09-51.25, seattle: 81.87-81.91). So per log, with M the largest reading:
// if at least two readings lie within kCarmenNoReturnBand of M, every reading
// >= M - kCarmenNoReturnBand is a no-return and max_range is that threshold;
// otherwise (no such code, e.g. a short synthetic log) max_range is just
// above M. Zero and subnormal (< 1.2e-38) readings are
// invalid too. A beam that reads exactly the same
// value in every one of at least kCarmenConstantBeamMinScans scans is not a
// measurement (acapulco's beam 180 reads 50.00 in all 861 scans) and is
// marked invalid. PARAM robot_front_laser_max is not used: it is wrong in
// edmonton (10 m, with many real returns up to 51 m).
// Since these decisions need every scan, the file is read twice, a line at a
// time (so a log of any length takes the memory of one line): once to parse
// every line and decide, once to hand out the steps.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "hmt/common/sensor_data.h"
#include "hmt/io/log_stream.h"

namespace hmt::io {

constexpr double kCarmenNoReturnBand = 0.3;        // metres
constexpr size_t kCarmenConstantBeamMinScans = 50;

// Throws hmt::InputError naming the file, the line number and the problem
// for wrong field counts, non-numeric / NaN / infinite fields, negative
// ranges, zero-beam scans; and for a missing, empty or scan-less file.
hmt::Log read_carmen(const std::string& path);

// The same steps as a stream (log_stream.h). Every line is parsed here,
// so the errors above are thrown before any step is handed out; a file
// that changes between the two passes is an error naming it.
std::unique_ptr<LogStream> open_carmen(const std::string& path);

// read_carmen(), and into *odometry each step's odometry pose as the log
// has it (absolute, in the log's odometry frame), which the steps hold only
// as increments: what a bag written from the log carries (bag_writer.h).
hmt::Log read_carmen(const std::string& path, std::vector<Pose2D>* odometry);

}  // namespace hmt::io

// MRPT rawlogs (binary, optionally gzip-compressed) <-> the internal stream.
//
// Both rawlog layouts are read:
//  - Actions/SensoryFrame: CActionCollection (odometry as a
//    CActionRobotMovement2D increment) alternating with CSensoryFrame (the
//    observations taken at one robot pose);
//  - observations only: a time-ordered sequence of CObservation objects,
//    odometry arriving as CObservationOdometry (absolute dead-reckoning pose).
// Every CObservation2DRangeScan becomes one hmt::LogStep, in file order;
// other observation types (images, sonar, GPS...) are skipped.
// Odometry comes from the robot movements if the file holds any, else from
// the odometry observations; a file whose movements start only after two
// odometry observations with a scan between them is refused as mixing the
// layouts (the reader streams, and decides the source as early as that:
// src/rawlog_collector.h). open_log() (log_stream.h) reads a rawlog entry
// by entry, through the MRPT plugin too.
#pragma once

#include <string>

#include "hmt/common/sensor_data.h"

namespace hmt::io {

// Reads a rawlog (gzip or plain). Throws hmt::InputError with a one-line
// message naming the file (and the entry / scan index where it applies) when
// the file is missing, empty, not a rawlog, truncated, holds no 2D scans,
// holds scans but no odometry, or holds NaN / negative / zero-beam scans,
// scans whose aperture is not in [0, 2 pi] or whose sensor pose is not
// finite.
//
// Conventions of the result (see sensor_data.h):
//  - angle_increment >= 0 always: scans stored left-to-right, or taken by a
//    sensor mounted upside down, are reversed so bearings increase;
//  - a reading is valid iff MRPT flags it valid, it is > 0 and < maxRange,
//    and not a subnormal float (< 1.2e-38 m: no distance a laser measures);
//    +inf readings are no-returns (stored as maxRange), NaN is an error;
//  - sensor_pose is the planar part (x, y, yaw) of the scan's sensorPose.
//
// The format is read natively for the classes laser/odometry rawlogs hold
// (see src/rawlog_objects.h), in every version MRPT 2.5.8 reads. A file that
// also holds other classes (camera images, GPS...) is read by MRPT itself,
// through a plugin loaded only then (src/mrpt_fallback.h); if the plugin
// cannot be loaded, the InputError names the class and the file.
//
// Limitation: MRPT's own deserializers do not check everything they read,
// so a file read through the plugin and damaged *inside* an object (flipped
// bits, not truncation) can crash MRPT 2.5.8. The native reader checks every
// read.
hmt::Log read_rawlog(const std::string& path);

enum class RawlogFormat { kActionsSensoryFrames, kObservationsOnly };

// Writes `log` as an MRPT rawlog, gzip-compressed iff `path` ends in ".gz",
// atomically (temporary file + rename), byte for byte as MRPT 2.5.8 writes
// the same objects (so its rbpf-slam reads it). Scans get sensorLabel "LASER",
// odometry "ODOMETRY"; timestamps are kept (to 100 ns, MRPT's resolution).
//  - kActionsSensoryFrames: per step a CActionCollection holding a
//    CActionRobotMovement2D made from the increment with MRPT's default
//    Gaussian motion model (none before the first step), then a
//    CSensoryFrame holding the scan;
//  - kObservationsOnly: per step a CObservationOdometry with the accumulated
//    pose (the first step at the origin), then the CObservation2DRangeScan.
// MRPT scans are symmetric about the sensor's x axis. A scan whose beams are
// not (CARMEN's 180 beams run from -90 to +89 degrees) is written with the
// sensor yaw turned by the asymmetry: every beam keeps its direction in the
// robot frame, but reading it back splits that direction differently between
// sensor_pose.theta and angle_min.
// Throws hmt::OutputError if the file cannot be written (nothing is left
// behind then), or if the log holds a step that cannot be represented.
void write_rawlog(const hmt::Log& log, const std::string& path,
                  RawlogFormat format);

// The same for the steps left in `log`, read as they are written (a long
// log is never held whole); returns how many were written. An error of the
// stream (hmt::InputError) leaves no file behind either.
class LogStream;  // log_stream.h
size_t write_rawlog(LogStream& log, const std::string& path, RawlogFormat format);

}  // namespace hmt::io

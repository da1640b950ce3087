// A scan prepared once per step for every particle: the end points used for
// matching, in the robot frame, each with the point one cell nearer the
// sensor (the "free" probe that tells the near side of a wall from the far).
#pragma once

#include <vector>

#include "hmt/common/pose2d.h"
#include "hmt/common/sensor_data.h"

namespace hmt::metric_slam {

struct ScanPoints {
  std::vector<Point2D> hit;   // end points, robot frame
  std::vector<Point2D> free;  // one `free_step` back along each beam
};

// Keeps valid beams with range <= max_range, every (skip+1)-th beam.
ScanPoints prepare_scan(const LaserScan& scan, double max_range, int skip,
                        double free_step);

// The distance from the robot within which three quarters of the points
// lie (0 without points). A heading error moves a point in proportion to its
// range, so this is the lever arm of the points that pin a heading down.
double far_range(const ScanPoints& pts);

// At most `max_points` points spread evenly over the scan (all if 0 or if
// the scan has no more).
ScanPoints spread_subset(const ScanPoints& pts, int max_points);

}  // namespace hmt::metric_slam

// Integrating a laser scan into an occupancy grid: cells crossed by a beam
// become more likely free, the cell of its end point more likely occupied
// (the inverse sensor model in log-odds form).
#pragma once

#include "hmt/common/config.h"
#include "hmt/common/pose2d.h"
#include "hmt/common/sensor_data.h"
#include "hmt/grid/occupancy_grid.h"

namespace hmt::grid {

struct InsertionOptions {
  double p_occupied = 0.7;   // inverse sensor model at a hit
  double p_free = 0.4;       // inverse sensor model along a beam
  double p_clamp = 0.97;     // log-odds are clamped to logit(+-p_clamp)
  double max_range = 20.0;   // beams longer than this mark free space only
                             // up to it, with no hit (far hits are noisy)
  // `max_insertion_range = auto` in the configuration (the default): the
  // scan matcher's max_range, whatever it resolves to (its owner sets it).
  bool range_from_matcher = true;

  void load(Config& cfg, const std::string& section = "grid");
  // Scaled integer log-odds increments.
  LogOdds l_occupied() const;
  LogOdds l_free() const;
  LogOdds l_clamp() const;
};

// Inserts `scan` taken with the robot at `robot_pose` (map frame).
void insert_scan(OccupancyGrid& grid, const Pose2D& robot_pose,
                 const LaserScan& scan, const InsertionOptions& opt);

}  // namespace hmt::grid

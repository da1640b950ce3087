// Where islands of reliability go (003 section 5): places whose R is high,
// spread over the map. Islands are the local maxima of R of at least
// `threshold`, no two closer than `min_distance`: the free cells in
// decreasing R (equal values in raster order), each kept unless a kept one
// lies within min_distance, so each island is the maximum of R within that
// distance among the cells not already claimed.
#pragma once

#include <vector>

#include "hmt/islands/distinctiveness.h"
#include "hmt/islands/occupancy_raster.h"

namespace hmt::islands {

struct Island {
  int id = 0;  // 1, 2, ... in decreasing R
  int i = 0;   // raster cell
  int j = 0;
  double x = 0.0;  // map-frame centre of the cell
  double y = 0.0;
  double r = 0.0;
};

std::vector<Island> choose_islands(const OccupancyRaster& map, const DistinctivenessMap& d,
                                   double threshold, double min_distance);

}  // namespace hmt::islands

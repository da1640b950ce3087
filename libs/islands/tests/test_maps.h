// Small occupancy rasters for the tests: walls drawn as segments on free
// space, and rotations of whole rasters.
#pragma once

#include <vector>

#include "hmt/islands/occupancy_raster.h"

namespace hmt::islands::test {

struct Segment {
  double x0, y0, x1, y1;  // metres, map frame
};

// A width x height metres raster at `res`: the cells the segments cross
// occupied, the others free if `free_boxes` is empty, else free inside the
// boxes (x0, y0)-(x1, y1) and unknown outside, as a mapped building is; the
// segments and boxes first rotated by `angle` about the raster's centre.
OccupancyRaster walls(double width, double height, double res,
                      const std::vector<Segment>& segments, double angle = 0.0,
                      const std::vector<Segment>& free_boxes = {});

// The raster turned 90 degrees counter-clockwise: cell (i, j) goes to
// (height - 1 - j, i).
OccupancyRaster rotate90(const OccupancyRaster& map);

}  // namespace hmt::islands::test

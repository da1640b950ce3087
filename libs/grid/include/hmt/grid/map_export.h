// Writing occupancy grids as images: PNG for people, PGM + YAML in the ROS
// map_server convention for tools. Unknown cells are grey (205), free white
// (254), occupied black (0); image row 0 is the top (largest y).
#pragma once

#include <string>

#include "hmt/grid/image.h"
#include "hmt/grid/occupancy_grid.h"

namespace hmt::grid {

struct MapImage {
  Image image;              // 1 channel, map_server grey levels
  double resolution = 0.0;  // metres per pixel
  double origin_x = 0.0;    // map-frame position of the lower-left pixel corner
  double origin_y = 0.0;
};

// Renders the allocated part of the grid (plus a margin in cells).
MapImage render(const OccupancyGrid& grid, int margin_cells = 10);

// Atomic writes; throw OutputError. write_png takes any image write_png_file
// (hmt/grid/png.h) does: the grey maps, and the colour pictures drawn on them.
void write_png(const MapImage& m, const std::string& path);
// Writes `<base>.pgm` and `<base>.yaml` (image: referenced by file name).
void write_pgm_yaml(const MapImage& m, const std::string& base_path);

}  // namespace hmt::grid

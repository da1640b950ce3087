// Writing occupancy grids as images: PNG for people, PGM + YAML in the ROS
// map_server convention for tools. Unknown cells are grey (205), free white
// (254), occupied black (0); image row 0 is the top (largest y).
#pragma once

#include <string>

#include "hmt/grid/image.h"
#include "hmt/grid/occupancy_grid.h"
#include "hmt/grid/row_source.h"

namespace hmt::grid {

// Where a map's image lies: its size in pixels (one per cell) and the
// map-frame position of its lower-left pixel corner.
struct MapFrame {
  int width = 0;
  int height = 0;
  double resolution = 0.0;  // metres per pixel
  double origin_x = 0.0;
  double origin_y = 0.0;
};

struct MapImage {
  Image image;              // 1 channel, map_server grey levels
  double resolution = 0.0;  // metres per pixel
  double origin_x = 0.0;    // map-frame position of the lower-left pixel corner
  double origin_y = 0.0;
  MapFrame frame() const {
    return {image.width(), image.height(), resolution, origin_x, origin_y};
  }
};

// The frame of the allocated part of the grid plus a margin in cells (a
// single unknown pixel at the origin for an empty grid).
MapFrame map_frame(const OccupancyGrid& grid, int margin_cells = 10);
// The grey rows [first_row, first_row + rows) of the grid's image in
// `frame`: a band (hmt/grid/image.h).
Image render_band(const OccupancyGrid& grid, const MapFrame& frame, int first_row, int rows);
// Renders the allocated part of the grid (plus a margin in cells): all the
// bands of map_frame() at once.
MapImage render(const OccupancyGrid& grid, int margin_cells = 10);

// The grid's image in `frame`, rendered band by band as it is written (the
// grid must outlive it).
class MapRows : public BandRows {
 public:
  MapRows(const OccupancyGrid& grid, const MapFrame& frame);

 protected:
  Image make_band(int first_row, int rows) override;

 private:
  const OccupancyGrid& grid_;
  MapFrame frame_;
};

// Atomic writes; throw OutputError. write_png takes any image write_png_file
// (hmt/grid/png.h) does: the grey maps, and the colour pictures drawn on them.
void write_png(const MapImage& m, const std::string& path);
// Writes `<base>.pgm` and `<base>.yaml` (image: referenced by file name).
void write_pgm_yaml(const MapImage& m, const std::string& base_path);
// The same from grey rows made as they are written, placed by `frame`.
void write_pgm_yaml(RowSource& rows, const MapFrame& frame, const std::string& base_path);

}  // namespace hmt::grid

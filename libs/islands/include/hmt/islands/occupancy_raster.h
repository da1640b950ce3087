// The map R is computed over: each cell free, occupied or unknown, on a
// regular raster placed in the map frame. Column i, row j is the cell
// [origin_x + i res, origin_x + (i+1) res) x [origin_y + j res, ...): rows
// go up (+y), unlike an image's.
#pragma once

#include <cstdint>
#include <vector>

#include "hmt/grid/map_export.h"

namespace hmt::islands {

// Free: a robot can be there (R is evaluated). Occupied: a wall, where rays
// hit. Unknown: never observed, where rays end unseen. Uncertain: observed
// but neither free nor occupied by the map's thresholds (a wall seen too
// few times, a cell at the edge of the laser's reach): rays pass through,
// as the laser did when it observed them, but R is not evaluated there.
enum class CellState : uint8_t { kFree = 0, kOccupied = 1, kUnknown = 2, kUncertain = 3 };

struct OccupancyRaster {
  int width = 0;
  int height = 0;
  double resolution = 0.0;  // metres per cell
  double origin_x = 0.0;    // map-frame position of cell (0, 0)'s lower-left corner
  double origin_y = 0.0;
  std::vector<CellState> cells;  // row-major, row 0 the bottom

  OccupancyRaster() = default;
  OccupancyRaster(int w, int h, double res, CellState fill = CellState::kUnknown);

  bool inside(int i, int j) const { return i >= 0 && j >= 0 && i < width && j < height; }
  size_t index(int i, int j) const {
    return static_cast<size_t>(j) * static_cast<size_t>(width) + static_cast<size_t>(i);
  }
  CellState at(int i, int j) const { return cells[index(i, j)]; }
  CellState& at(int i, int j) { return cells[index(i, j)]; }
  // Map-frame centre of a cell.
  double x_of(int i) const { return origin_x + (i + 0.5) * resolution; }
  double y_of(int j) const { return origin_y + (j + 0.5) * resolution; }
};

// The map_server reading of a grey map image (hmt/grid/map_export.h): p =
// (255 - v) / 255 (or v / 255 when negated) is occupied above
// occupied_thresh, free below free_thresh; between them, the grey level 205
// that map_server's map_saver (and this project's writer) gives cells never
// observed is unknown, any other uncertain.
struct GreyThresholds {
  double occupied = 0.65;
  double free = 0.196;
  bool negate = false;
};
OccupancyRaster classify(const grid::MapImage& map, const GreyThresholds& thresholds = {});

}  // namespace hmt::islands

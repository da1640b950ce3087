// The surface normal at each occupied cell of a grid, computed once per map
// so that each ray hit of the distinctiveness measure only looks it up. The
// paper's line segments (003 section 6) have one normal each; a grid has
// none, so the normal is estimated from the occupied cells around the hit:
// the minor principal axis of their positions, as a wall's cells lie along
// it. How little the neighbourhood looks like a wall is kept too: its
// isotropy l2 / l1, the ratio of the minor to the major principal variance,
// 0 for a straight line of cells, 1 for an isolated cell or a round blob,
// which constrains the robot along the viewing direction instead (a post
// seen from anywhere faces the viewer). The ratio rather than, say, 1 - (l1
// - l2) / (l1 + l2): a wall drawn at a slant is a staircase of cells whose
// minor variance (about 1/12 cell^2) stays small against the major one, and
// the ratio keeps such a wall a wall.
#pragma once

#include <vector>

#include "hmt/islands/occupancy_raster.h"

namespace hmt::islands {

struct SurfaceNormals {
  // Per cell of the raster (row-major); meaningful at occupied cells only.
  std::vector<float> nx, ny;     // unit normal (its sign is arbitrary)
  std::vector<float> isotropy;  // in [0, 1]
};

// `radius_cells`: the occupied cells within this many cells (Euclidean) of a
// cell are its neighbourhood (>= 1, else std::invalid_argument).
SurfaceNormals surface_normals(const OccupancyRaster& map, double radius_cells);

}  // namespace hmt::islands

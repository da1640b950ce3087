// One occupancy grid of the whole map (002 section IV-C, Fig. 7(e)-(f)): each
// area's archived local grid drawn at the area's global pose.
#pragma once

#include "hmt/global_map/global_poses.h"
#include "hmt/grid/occupancy_grid.h"
#include "hmt/topology/hmt_map.h"

namespace hmt::global_map {

// Draws every area that has a map and a pose in `poses` into a new grid of
// the given resolution, in the root's frame. Each cell of the new grid that
// falls inside an area map's rotated bounding box takes the area cell under
// its centre (nearest neighbour, the pose's inverse applied to the centre).
//
// Where areas overlap their log-odds are added: the local maps are
// independent evidence about the same place (each built from its own
// scans), and the sum of log-odds is the product of their likelihood ratios.
// The sum saturates at +-127 (the symmetric range of the int8 cell, the same
// bound the scan insertion keeps its hit offsets in). Hit counts take the
// maximum over the areas (a count, not evidence); the hit offsets are left
// at the cell centre, since a rotated sub-cell offset no longer belongs to
// the nearest-neighbour cell it was read from. Unknown area cells (never
// observed, log-odds 0 and no hits) are not copied, so the new grid
// allocates tiles only where some area saw something.
//
// Areas without a map, and areas absent from `poses` (unreachable from the
// root), are skipped. Throws std::invalid_argument for a resolution that is
// not positive and finite, or for poses of an area the map does not have
// (poses computed for another map).
grid::OccupancyGrid render_global_grid(const topology::HmtMap& map,
                                       const GlobalPoses& poses,
                                       double resolution);

}  // namespace hmt::global_map

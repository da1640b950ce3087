// The maps `hmt-slam islands` reads:
//  - a ROS map_server map: its .yaml (image, resolution, origin, negate,
//    occupied_thresh, free_thresh) or its .pgm beside a .yaml of the same
//    name (the map.pgm + map.yaml a run writes);
//  - a run's hmt_map.bin (topology::save_session): the most probable
//    hypothesis's areas drawn into one grid at their least-squares global
//    poses (global_map::render_global_grid), the shortest-path tree if the
//    optimisation fails. That is the area-grain map of [global_map] method
//    = areas: the file holds the areas' grids but not the log the keyframe
//    graph redraws its map from. R is computed over the whole map rather
//    than per area because the sensor at a place near an area's border sees
//    the neighbouring area's walls too.
// Any failure (missing file, unknown format, malformed header or values) is
// an hmt::InputError naming the file and the problem.
#pragma once

#include <string>

#include "hmt/grid/map_export.h"
#include "hmt/islands/occupancy_raster.h"

namespace hmt::islands {

struct LoadedMap {
  grid::MapImage image;  // grey, map_server levels (for drawing on)
  GreyThresholds thresholds;
  std::string description;  // what was read, for the user
  OccupancyRaster raster() const { return classify(image, thresholds); }
  // The same with walls above `wall_probability` instead of the map's own
  // occupied threshold ([islands] wall_probability).
  OccupancyRaster raster(double wall_probability) const {
    GreyThresholds t = thresholds;
    t.occupied = wall_probability;
    return classify(image, t);
  }
};

LoadedMap load_map(const std::string& path);

// The parts, for tests and other readers.
grid::Image read_pgm(const std::string& path);
LoadedMap read_map_yaml(const std::string& yaml_path);
LoadedMap read_hmt_map(const std::string& bin_path);

}  // namespace hmt::islands

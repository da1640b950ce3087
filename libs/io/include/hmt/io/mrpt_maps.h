// Maps written in MRPT's own formats, for MRPT's tools: pf-localization
// localizes in them, RawLogViewer and the map viewers open them.
//
//  - a .gridmap.gz: an mrpt::maps::COccupancyGridMap2D serialized with
//    MRPT's archive into a gzip stream (CFileGZOutputStream), as MRPT's own
//    programs write grid maps;
//  - a .simplemap: an mrpt::maps::CSimpleMap, one (pose, sensory frame) pair
//    per keyframe: the pose a CPose3DPDFGaussian (x, y, yaw with their
//    covariance; z, pitch, roll exactly 0), the frame one
//    CObservation2DRangeScan with the keyframe's scan (beam directions kept
//    as rawlog.h describes), gzip-compressed as CSimpleMap::saveToFile()
//    writes it.
//
// MRPT itself writes them, through the plugin libhmt_io_mrpt_maps.so, loaded
// with dlopen() only when maps are written (HMT_IO_MRPT_MAPS_PLUGIN
// overrides where it is looked for; plugin_loader.h lists the places).
// Both are written atomically: to a temporary sibling, then renamed.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "hmt/common/pose_gaussian.h"
#include "hmt/common/sensor_data.h"

namespace hmt::io {

struct MrptGridMap {
  double resolution = 0.05;       // cell size (m)
  double x_min = 0.0, y_min = 0.0;  // lower-left corner of cell (0, 0) (m)
  int size_x = 0, size_y = 0;     // cells
  // P(occupied) of cell (cx, cy), 0 <= cx < size_x, 0 <= cy < size_y, cy
  // growing with y; 0.5 for unknown space. Called once per cell.
  std::function<float(int cx, int cy)> occupancy;
};

struct MapKeyframe {
  PoseGaussian pose;  // the robot in the map's frame
  LaserScan scan;     // its timestamp is the observation's
};

// Throws std::invalid_argument for a grid without cells, a resolution that
// is not positive and finite, or no occupancy function; OutputError when the
// plugin cannot be loaded or the file cannot be written.
void write_mrpt_gridmap(const MrptGridMap& grid, const std::string& path);

// Throws std::invalid_argument for a keyframe whose scan has no beams or a
// covariance that is not finite; OutputError as write_mrpt_gridmap().
void write_mrpt_simplemap(const std::vector<MapKeyframe>& keyframes, const std::string& path);

}  // namespace hmt::io

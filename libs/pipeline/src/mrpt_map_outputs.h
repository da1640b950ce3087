// `[output] mrpt_maps = true`: the run's map and keyframes in MRPT's formats
// (hmt/io/mrpt_maps.h), written by MRPT through its plugin.
//  map.gridmap.gz        the global map (map.png's cells and extent) as a
//                        COccupancyGridMap2D
//  keyframes.simplemap   a CSimpleMap: every keyframe the global map was
//                        drawn from, at its global pose, with its scan
#pragma once

#include <string>
#include <vector>

#include "hmt/common/sensor_data.h"
#include "hmt/global_map/global_map_options.h"
#include "hmt/global_map/global_poses.h"
#include "hmt/global_map/keyframe_graph.h"
#include "hmt/grid/map_export.h"
#include "hmt/grid/occupancy_grid.h"

namespace hmt::pipeline {

// The keyframes of the area visits when no keyframe graph placed them
// ([global_map] method = areas, or its failure): along each visit, a
// keyframe every `opt` keyframe_distance / keyframe_angle of in-area motion
// (the first step of a visit always; the step a visit shares with the next
// is the next one's), placed by its area's global pose, as the trajectory
// places the step.
std::vector<global_map::KeyframeNode> visit_keyframes(
    const std::vector<global_map::AreaVisit>& visits, const global_map::GlobalPoses& poses,
    const global_map::KeyframeGraphOptions& opt);

// Writes map.gridmap.gz (the cells of `grid` inside `frame`) and
// keyframes.simplemap (each node whose step `steps` holds). A keyframe's
// covariance: its area frame's marginal covariance carried to the keyframe,
// plus the in-area uncertainty of [global_map] in_area_std_*. Throws
// OutputError.
void write_mrpt_map_outputs(const grid::OccupancyGrid& grid, const grid::MapFrame& frame,
                            const std::vector<global_map::KeyframeNode>& nodes,
                            const global_map::GlobalPoses& poses,
                            const global_map::KeyframeGraphOptions& opt,
                            const global_map::StepSource& steps, const std::string& out_dir);

}  // namespace hmt::pipeline

// What the keyframe graph (keyframe_graph.h) gives a person: the robot's
// trajectory and one occupancy grid in the global frame.
//
// Trajectory: every log step is placed from the keyframe nodes of its own
// area visit on either side of it along the path, by the in-area path
// between each and the step (the node's optimised pose composed with the
// step's pose seen from the node's, both in the area's frame), the two
// blended by how far along the path from one node to the next the step
// lies; before a visit's first node or after its last, from that node
// alone. A step never depends on another visit's area pose, so the
// trajectory has no jumps at area switches, nor where the graph corrected
// two consecutive nodes differently.
//
// Grid: the keyframe scans inserted (grid::insert_scan) at their optimised
// poses into one grid, in path order: one map made from the aligned scans,
// not the areas' grids pasted as rigid blocks, so a wall seen from several
// areas is drawn once where the graph put it.
#pragma once

#include <cstdint>
#include <vector>

#include "hmt/global_map/keyframe_graph.h"
#include "hmt/grid/occupancy_grid.h"
#include "hmt/grid/scan_insertion.h"

namespace hmt::global_map {

// One pose per log step from `first` on (`count` of them). A step of no
// visit, or of a visit without a node, repeats the pose before it (the
// identity before the first placed step).
std::vector<Pose2D> keyframe_trajectory(const std::vector<AreaVisit>& visits,
                                        const std::vector<KeyframeNode>& nodes, uint64_t first,
                                        size_t count);

// The nodes' scans inserted at their global poses into a new grid of the
// given resolution. Nodes whose step `steps` does not hold are skipped.
// Throws std::invalid_argument for a resolution that is not positive and
// finite.
grid::OccupancyGrid render_keyframe_grid(const std::vector<KeyframeNode>& nodes,
                                         const StepSource& steps, double resolution,
                                         const grid::InsertionOptions& insertion);

}  // namespace hmt::global_map

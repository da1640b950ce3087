// Pictures of a grouping: the SSO weight matrix as an image, before and
// after reordering by group (000 Fig. 9, middle and right columns; 001 Fig.
// 3f), and the groups drawn in colour over a global map (000 Fig. 9, left).
#pragma once

#include <vector>

#include "hmt/area/ncut.h"
#include "hmt/common/pose2d.h"
#include "hmt/grid/image.h"
#include "hmt/grid/map_export.h"

namespace hmt::grouping {

// A distinct BGR colour per group (a fixed 12-colour palette, cycled).
grid::Bgr group_colour(int group);

// W as a grey image, rows and columns in `order` (a permutation of the
// nodes): pixel brightness = SSO (black 0, white 1), the diagonal white (an
// observation overlaps itself fully). Each matrix cell is a square of
// max(1, target_px / n) pixels; above 2000 nodes cells are pooled by their
// maximum so that the side stays at most 2000 pixels. `block_sizes` (in
// order, summing to n; may be empty) outline diagonal blocks in their
// group's colour. BGR.
grid::Image weight_image(const area::WeightMatrix& W, const std::vector<int>& order,
                         const std::vector<int>& block_sizes, int target_px = 800);

struct MapOverlay {
  // Per keyframe: its pose in the map's frame, its group, and its scan's end
  // points in that frame.
  std::vector<Pose2D> pose;
  std::vector<int> group;
  std::vector<std::vector<Point2D>> points;
  int groups = 0;
};

// The rendered map in grey, each keyframe's end points in its group's
// colour, the route as a thin dark line through the keyframes, each keyframe
// a dot in its group's colour, and each group's id at the keyframe nearest
// to the mean of its keyframes' positions, outlined in white. BGR.
grid::Image groups_map_image(const grid::MapImage& map, const MapOverlay& overlay);

}  // namespace hmt::grouping

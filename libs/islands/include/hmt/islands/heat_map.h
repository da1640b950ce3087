// Pictures of the distinctiveness measure: R as a colour over the grey map,
// with a colour bar, and the islands marked with their ids.
#pragma once

#include <vector>

#include "hmt/grid/image.h"
#include "hmt/grid/map_export.h"
#include "hmt/islands/distinctiveness.h"
#include "hmt/islands/island_choice.h"

namespace hmt::islands {

// R in [0, 1] as a colour of the viridis scale (dark purple, blue, green,
// yellow: ordered in lightness, readable in grey), linear between nine
// anchors; values outside are clamped.
grid::Bgr colour_of(double r);

// The grey map with each cell that has an R in its colour, a colour bar to
// the right (0 at the bottom, 1 at the top, a tick every 0.25, a white mark
// at `threshold`), and the islands. The map's pixels keep their place
// (column x, row y of `map`'s image), so the image lines up with map.png.
grid::Image heat_map_image(const grid::MapImage& map, const DistinctivenessMap& d,
                           const std::vector<Island>& islands, double threshold);

// The grey map in colour with the islands: a filled circle each, outlined
// in white, its id beside it.
grid::Image islands_image(const grid::MapImage& map, const std::vector<Island>& islands);

// Draws the islands on an image of `map`'s size or wider.
void draw_islands(grid::Image& image, int map_height, const std::vector<Island>& islands);

}  // namespace hmt::islands

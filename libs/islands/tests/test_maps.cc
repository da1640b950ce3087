#include "test_maps.h"

#include <algorithm>
#include <cmath>

namespace hmt::islands::test {

OccupancyRaster walls(double width, double height, double res,
                      const std::vector<Segment>& segments, double angle,
                      const std::vector<Segment>& free_boxes) {
  const int w = static_cast<int>(std::lround(width / res));
  const int h = static_cast<int>(std::lround(height / res));
  OccupancyRaster r(w, h, res, free_boxes.empty() ? CellState::kFree : CellState::kUnknown);
  const double cx = width / 2, cy = height / 2, c = std::cos(angle), s = std::sin(angle);
  for (int j = 0; j < h && !free_boxes.empty(); ++j)
    for (int i = 0; i < w; ++i) {
      // The cell's centre turned back into the boxes' frame.
      const double x = r.x_of(i) - cx, y = r.y_of(j) - cy;
      const double bx = cx + c * x + s * y, by = cy - s * x + c * y;
      for (const Segment& b : free_boxes)
        if (bx >= b.x0 && bx <= b.x1 && by >= b.y0 && by <= b.y1) r.at(i, j) = CellState::kFree;
    }
  const auto turn = [&](double x, double y, double* ox, double* oy) {
    *ox = cx + c * (x - cx) - s * (y - cy);
    *oy = cy + s * (x - cx) + c * (y - cy);
  };
  for (const Segment& g : segments) {
    double ax, ay, bx, by;
    turn(g.x0, g.y0, &ax, &ay);
    turn(g.x1, g.y1, &bx, &by);
    const double len = std::hypot(bx - ax, by - ay);
    const int steps = std::max(1, static_cast<int>(std::ceil(len / (0.25 * res))));
    for (int k = 0; k <= steps; ++k) {
      const double t = static_cast<double>(k) / steps;
      const int i = static_cast<int>(std::floor((ax + t * (bx - ax)) / res));
      const int j = static_cast<int>(std::floor((ay + t * (by - ay)) / res));
      if (r.inside(i, j)) r.at(i, j) = CellState::kOccupied;
    }
  }
  return r;
}

OccupancyRaster rotate90(const OccupancyRaster& m) {
  OccupancyRaster r(m.height, m.width, m.resolution);
  for (int j = 0; j < m.height; ++j)
    for (int i = 0; i < m.width; ++i) r.at(m.height - 1 - j, i) = m.at(i, j);
  return r;
}

}  // namespace hmt::islands::test

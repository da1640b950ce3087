#include "hmt/islands/surface_normals.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hmt::islands {

SurfaceNormals surface_normals(const OccupancyRaster& map, double radius_cells) {
  if (!(radius_cells >= 1.0)) throw std::invalid_argument("surface_normals: radius below 1 cell");
  const size_t n = map.cells.size();
  SurfaceNormals out;
  out.nx.assign(n, 0.0f);
  out.ny.assign(n, 0.0f);
  out.isotropy.assign(n, 1.0f);
  const int r = static_cast<int>(std::floor(radius_cells));
  const double r2 = radius_cells * radius_cells;
  for (int j = 0; j < map.height; ++j)
    for (int i = 0; i < map.width; ++i) {
      if (map.at(i, j) != CellState::kOccupied) continue;
      // Second moments of the occupied offsets about their mean.
      double cnt = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
      for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
          if (dx * dx + dy * dy > r2 || !map.inside(i + dx, j + dy) ||
              map.at(i + dx, j + dy) != CellState::kOccupied)
            continue;
          cnt += 1;
          sx += dx;
          sy += dy;
          sxx += dx * dx;
          syy += dy * dy;
          sxy += dx * dy;
        }
      const double mx = sx / cnt, my = sy / cnt;
      const double cxx = sxx / cnt - mx * mx, cyy = syy / cnt - my * my,
                   cxy = sxy / cnt - mx * my;
      const double half_diff = 0.5 * (cxx - cyy);
      const double root = std::sqrt(half_diff * half_diff + cxy * cxy);
      const double trace = cxx + cyy;
      const size_t k = map.index(i, j);
      // Major axis at 0.5 atan2(2 cxy, cxx - cyy); the normal is across it.
      const double major = 0.5 * std::atan2(2.0 * cxy, cxx - cyy);
      out.nx[k] = static_cast<float>(-std::sin(major));
      out.ny[k] = static_cast<float>(std::cos(major));
      const double major_var = 0.5 * trace + root, minor_var = 0.5 * trace - root;
      out.isotropy[k] =
          major_var > 0 ? static_cast<float>(std::clamp(minor_var / major_var, 0.0, 1.0)) : 1.0f;
    }
  return out;
}

}  // namespace hmt::islands

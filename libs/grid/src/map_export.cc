#include "hmt/grid/map_export.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "hmt/common/files.h"
#include "hmt/grid/png.h"

namespace hmt::grid {

MapImage render(const OccupancyGrid& grid, int margin) {
  MapImage out;
  out.resolution = grid.resolution();
  CellIndex lo, hi;
  if (!grid.bounds(&lo, &hi)) {
    out.image = Image(1, 1, 1, 205);
    return out;
  }
  lo.x -= margin;
  lo.y -= margin;
  hi.x += margin;
  hi.y += margin;
  const int w = hi.x - lo.x + 1, h = hi.y - lo.y + 1;
  out.image = Image(w, h, 1, 205);
  out.origin_x = lo.x * grid.resolution();
  out.origin_y = lo.y * grid.resolution();
  for (int r = 0; r < h; ++r) {
    uint8_t* row = out.image.row(r);
    const int cy = hi.y - r;
    for (int col = 0; col < w; ++col) {
      const LogOdds l = grid.logodds({lo.x + col, cy});  // 0 in unknown space
      if (l == 0) continue;
      // map_server reads p = (255 - v) / 255: occupied above 0.65, free below
      // 0.196. Keep the grey level continuous in the probability.
      const double p = 1.0 / (1.0 + std::exp(-l / kLogOddsScale));
      row[col] = static_cast<uint8_t>(std::lround(254.0 * (1.0 - p)));
    }
  }
  return out;
}

void write_png(const MapImage& m, const std::string& path) {
  write_png_file(m.image, path);
}

void write_pgm_yaml(const MapImage& m, const std::string& base) {
  const std::string pgm = base + ".pgm";
  write_file_atomically(pgm, [&](std::ostream& os) {
    os << "P5\n# HMT-SLAM occupancy grid\n"
       << m.image.width() << " " << m.image.height() << "\n255\n";
    for (int r = 0; r < m.image.height(); ++r)
      os.write(reinterpret_cast<const char*>(m.image.row(r)), m.image.width());
  });
  char yaml[512];
  std::snprintf(yaml, sizeof yaml,
                "image: %s\nresolution: %.6f\norigin: [%.6f, %.6f, 0.0]\n"
                "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n",
                std::filesystem::path(pgm).filename().c_str(), m.resolution,
                m.origin_x, m.origin_y);
  write_text_atomically(base + ".yaml", yaml);
}

}  // namespace hmt::grid

#include "hmt/grid/map_export.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "hmt/common/files.h"
#include "hmt/grid/png.h"

namespace hmt::grid {
namespace {

// Rows per band when rendering for the writers: a few megabytes at most.
constexpr int kBandRows = 256;

// The grey level of each log-odds value: map_server reads p = (255 - v) /
// 255, occupied above 0.65, free below 0.196; the level stays continuous in
// the probability. Unknown space (0) is 205.
const std::array<uint8_t, 256>& grey_levels() {
  static const std::array<uint8_t, 256> table = [] {
    std::array<uint8_t, 256> t{};
    for (int i = 0; i < 256; ++i) {
      const int l = i - 128;
      const double p = 1.0 / (1.0 + std::exp(-l / kLogOddsScale));
      t[static_cast<size_t>(i)] =
          l == 0 ? 205 : static_cast<uint8_t>(std::lround(254.0 * (1.0 - p)));
    }
    return t;
  }();
  return table;
}

void write_yaml(const MapFrame& frame, const std::string& base, const std::string& pgm) {
  char yaml[512];
  std::snprintf(yaml, sizeof yaml,
                "image: %s\nresolution: %.6f\norigin: [%.6f, %.6f, 0.0]\n"
                "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n",
                std::filesystem::path(pgm).filename().c_str(), frame.resolution,
                frame.origin_x, frame.origin_y);
  write_text_atomically(base + ".yaml", yaml);
}

}  // namespace

MapFrame map_frame(const OccupancyGrid& grid, int margin) {
  MapFrame f;
  f.resolution = grid.resolution();
  CellIndex lo, hi;
  if (!grid.bounds(&lo, &hi)) {
    f.width = f.height = 1;
    return f;
  }
  lo.x -= margin;
  lo.y -= margin;
  hi.x += margin;
  hi.y += margin;
  f.width = hi.x - lo.x + 1;
  f.height = hi.y - lo.y + 1;
  f.origin_x = lo.x * grid.resolution();
  f.origin_y = lo.y * grid.resolution();
  return f;
}

Image render_band(const OccupancyGrid& grid, const MapFrame& frame, int first_row, int rows) {
  Image out = Image::band(frame.width, frame.height, first_row, rows, 1, 205);
  // The frame's cells: column 0 is lo.x, row 0 is hi.y (the top).
  const int lo_x = static_cast<int>(std::lround(frame.origin_x / frame.resolution));
  const int hi_y = static_cast<int>(std::lround(frame.origin_y / frame.resolution)) +
                   frame.height - 1;
  const std::array<uint8_t, 256>& grey = grey_levels();
  for (int r = first_row; r < first_row + rows; ++r) {
    uint8_t* row = out.row(r);
    const int cy = hi_y - r;
    for (int col = 0; col < frame.width; ++col) {
      const LogOdds l = grid.logodds({lo_x + col, cy});  // 0 in unknown space
      row[col] = grey[static_cast<size_t>(static_cast<int>(l) + 128)];
    }
  }
  return out;
}

MapImage render(const OccupancyGrid& grid, int margin) {
  const MapFrame f = map_frame(grid, margin);
  MapImage out;
  out.resolution = f.resolution;
  out.origin_x = f.origin_x;
  out.origin_y = f.origin_y;
  out.image = render_band(grid, f, 0, f.height);
  return out;
}

MapRows::MapRows(const OccupancyGrid& grid, const MapFrame& frame)
    : BandRows(frame.width, frame.height, 1, kBandRows), grid_(grid), frame_(frame) {}

Image MapRows::make_band(int first_row, int rows) {
  return render_band(grid_, frame_, first_row, rows);
}

void write_png(const MapImage& m, const std::string& path) {
  write_png_file(m.image, path);
}

void write_pgm_yaml(RowSource& rows, const MapFrame& frame, const std::string& base) {
  const std::string pgm = base + ".pgm";
  write_file_atomically(pgm, [&](std::ostream& os) {
    os << "P5\n# HMT-SLAM occupancy grid\n" << rows.width() << " " << rows.height() << "\n255\n";
    for (int r = 0; r < rows.height(); ++r)
      os.write(reinterpret_cast<const char*>(rows.row(r)), rows.width());
  });
  write_yaml(frame, base, pgm);
}

void write_pgm_yaml(const MapImage& m, const std::string& base) {
  ImageRows rows(m.image);
  write_pgm_yaml(rows, m.frame(), base);
}

}  // namespace hmt::grid

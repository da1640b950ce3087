#include "hmt/islands/occupancy_raster.h"

#include <stdexcept>

namespace hmt::islands {

namespace {
constexpr uint8_t kUnknownLevel = 205;
}  // namespace

OccupancyRaster::OccupancyRaster(int w, int h, double res, CellState fill)
    : width(w), height(h), resolution(res) {
  if (w < 0 || h < 0) throw std::invalid_argument("OccupancyRaster: negative size");
  cells.assign(static_cast<size_t>(w) * static_cast<size_t>(h), fill);
}

OccupancyRaster classify(const grid::MapImage& map, const GreyThresholds& t) {
  const grid::Image& img = map.image;
  if (img.channels() != 1) throw std::invalid_argument("classify: the map is not grey");
  OccupancyRaster r(img.width(), img.height(), map.resolution);
  r.origin_x = map.origin_x;
  r.origin_y = map.origin_y;
  for (int row = 0; row < img.height(); ++row) {
    const int j = img.height() - 1 - row;  // image row 0 is the top
    for (int i = 0; i < img.width(); ++i) {
      const uint8_t level = img.at(i, row);
      const double v = level / 255.0;
      const double p = t.negate ? v : 1.0 - v;
      r.at(i, j) = p > t.occupied ? CellState::kOccupied
                   : p < t.free   ? CellState::kFree
                   : level == kUnknownLevel ? CellState::kUnknown
                                            : CellState::kUncertain;
    }
  }
  return r;
}

}  // namespace hmt::islands

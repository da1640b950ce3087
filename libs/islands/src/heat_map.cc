#include "hmt/islands/heat_map.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "hmt/grid/draw.h"

namespace hmt::islands {
namespace {

// Width of the colour-bar panel, its bar, and the smallest image height that
// leaves the bar readable on a small map.
constexpr int kPanel = 64;
constexpr int kBarWidth = 18;
constexpr int kMinHeight = 160;
const grid::Bgr kIsland{255, 0, 255};  // magenta: not on the viridis scale

}  // namespace

grid::Bgr colour_of(double r) {
  // viridis at 0, 1/8, ..., 1 (R, G, B).
  static const double kAnchors[9][3] = {{68, 1, 84},    {71, 44, 122},  {59, 81, 139},
                                        {44, 113, 142}, {33, 144, 141}, {39, 173, 129},
                                        {92, 200, 99},  {170, 220, 50}, {253, 231, 37}};
  const double v = std::clamp(std::isnan(r) ? 0.0 : r, 0.0, 1.0) * 8.0;
  const int k = std::min(7, static_cast<int>(v));
  const double f = v - k;
  const auto mix = [&](int c) {
    return static_cast<uint8_t>(std::lround(kAnchors[k][c] + f * (kAnchors[k + 1][c] - kAnchors[k][c])));
  };
  return {mix(2), mix(1), mix(0)};
}

void draw_islands(grid::Image& img, int map_height, const std::vector<Island>& islands) {
  const int scale = img.width() >= 600 ? 2 : 1;
  const double radius = 3.0 * scale;
  for (const Island& is : islands) {
    const grid::Pixel p{static_cast<double>(is.i), static_cast<double>(map_height - 1 - is.j)};
    grid::fill_circle(img, p, radius + 1.5, grid::Bgr{255, 255, 255});
    grid::fill_circle(img, p, radius, kIsland);
    const std::string id = std::to_string(is.id);
    const int x = static_cast<int>(p.x + radius + 2);
    const int y = static_cast<int>(p.y - radius);
    // The id outlined in white so it reads on any background.
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        grid::draw_digits(img, id, x + dx, y + dy, scale, grid::Bgr{255, 255, 255});
    grid::draw_digits(img, id, x, y, scale, kIsland);
  }
}

grid::Image heat_map_image(const grid::MapImage& map, const DistinctivenessMap& d,
                           const std::vector<Island>& islands, double threshold) {
  const int mw = map.image.width(), mh = map.image.height();
  const int h = std::max(mh, kMinHeight);
  grid::Image img(mw + kPanel, h, 3, 255);
  for (int y = 0; y < mh; ++y)
    for (int x = 0; x < mw; ++x) {
      const float r = d.r[static_cast<size_t>(mh - 1 - y) * mw + x];
      const grid::Bgr c = std::isnan(r) ? grid::Bgr::grey(map.image.at(x, y)) : colour_of(r);
      img.at(x, y, 0) = c.b;
      img.at(x, y, 1) = c.g;
      img.at(x, y, 2) = c.r;
    }
  draw_islands(img, mh, islands);

  // The colour bar: from 0 (bottom) to 1 (top), 10 % of the height free at
  // each end for the labels.
  const int top = h / 10, bottom = h - 1 - h / 10;
  const int x0 = mw + 12, x1 = x0 + kBarWidth - 1;
  const auto row_of = [&](double v) {
    return static_cast<int>(std::lround(bottom - v * (bottom - top)));
  };
  for (int y = top; y <= bottom; ++y)
    grid::fill_rect(img, x0, y, x1, y, colour_of(static_cast<double>(bottom - y) / (bottom - top)));
  grid::draw_rect(img, x0 - 1, top - 1, x1 + 1, bottom + 1, grid::Bgr::grey(0));
  for (int t = 0; t <= 4; ++t)
    grid::fill_rect(img, x1 + 2, row_of(t / 4.0), x1 + 5, row_of(t / 4.0), grid::Bgr::grey(0));
  const int ty = row_of(threshold);
  grid::fill_rect(img, x0, ty, x1, ty, grid::Bgr{255, 255, 255});
  grid::fill_rect(img, x0 - 4, ty, x0 - 2, ty, kIsland);
  const int scale = 2;
  grid::draw_digits(img, "1", x1 + 8, top + grid::kGlyphHeight * scale / 2, scale, grid::Bgr::grey(0));
  grid::draw_digits(img, "0", x1 + 8, bottom + grid::kGlyphHeight * scale / 2, scale,
                    grid::Bgr::grey(0));
  return img;
}

grid::Image islands_image(const grid::MapImage& map, const std::vector<Island>& islands) {
  grid::Image img = grid::grey_to_bgr(map.image);
  draw_islands(img, map.image.height(), islands);
  return img;
}

}  // namespace hmt::islands

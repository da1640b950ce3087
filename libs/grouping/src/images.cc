#include "hmt/grouping/images.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "hmt/grid/draw.h"

namespace hmt::grouping {

grid::Bgr group_colour(int group) {
  // Tableau-like palette, BGR.
  static const grid::Bgr kPalette[] = {
      {180, 119, 31}, {14, 127, 255}, {44, 160, 44},  {40, 39, 214},
      {189, 103, 148}, {75, 86, 140}, {194, 119, 227}, {34, 189, 188},
      {207, 190, 23}, {0, 0, 128},    {128, 128, 0},  {60, 20, 220}};
  constexpr int kN = sizeof(kPalette) / sizeof(kPalette[0]);
  return kPalette[((group % kN) + kN) % kN];
}

grid::Image weight_image(const area::WeightMatrix& W, const std::vector<int>& order,
                         const std::vector<int>& block_sizes, int target_px) {
  const int n = static_cast<int>(W.rows());
  if (W.cols() != n || static_cast<int>(order.size()) != n)
    throw std::invalid_argument("weight_image: order is not over W's nodes");
  if (n == 0) return grid::Image(1, 1, 3, 0);
  // position of each node in the image
  std::vector<int> pos(n, -1);
  for (int k = 0; k < n; ++k) {
    const int v = order[k];
    if (v < 0 || v >= n || pos[v] >= 0)
      throw std::invalid_argument("weight_image: order is not a permutation");
    pos[v] = k;
  }
  constexpr int kMaxSide = 2000;
  // Cell k covers pixels [k * side / n, (k + 1) * side / n).
  const int scale = std::max(1, target_px / n);
  const int side = n > kMaxSide ? kMaxSide : n * scale;
  const auto px = [&](int k) {
    return static_cast<int>(static_cast<long long>(k) * side / n);
  };
  grid::Image grey(side, side, 1, 0);
  const auto paint = [&](int r, int c, double w) {
    const uint8_t v = static_cast<uint8_t>(
        std::lround(255.0 * std::clamp(w, 0.0, 1.0)));
    const int r0 = px(r), r1 = std::max(px(r + 1), r0 + 1);
    const int c0 = px(c), c1 = std::max(px(c + 1), c0 + 1);
    for (int y = r0; y < r1 && y < side; ++y) {
      uint8_t* row = grey.row(y);
      for (int x = c0; x < c1 && x < side; ++x) row[x] = std::max(row[x], v);
    }
  };
  for (int c = 0; c < W.outerSize(); ++c)
    for (area::WeightMatrix::InnerIterator it(W, c); it; ++it)
      if (it.row() != c) paint(pos[it.row()], pos[c], it.value());
  for (int k = 0; k < n; ++k) paint(k, k, 1.0);

  grid::Image img = grid::grey_to_bgr(grey);
  int start = 0;
  for (size_t g = 0; g < block_sizes.size(); ++g) {
    const int end = start + block_sizes[g];
    if (block_sizes[g] <= 0 || end > n)
      throw std::invalid_argument("weight_image: bad block sizes");
    const int thick = side >= 400 ? 2 : 1;
    const int last = std::max(px(end) - 1, px(start));
    grid::draw_rect(img, px(start), px(start), last, last,
                    group_colour(static_cast<int>(g)), thick);
    start = end;
  }
  return img;
}

grid::Image groups_map_image(const grid::MapImage& map, const MapOverlay& ov) {
  grid::Image img = grid::grey_to_bgr(map.image);
  const double res = map.resolution;
  const int rows = img.height();
  // Pixel of a map-frame point (row 0 is the top, the largest y).
  struct Px {
    int x, y;
  };
  const auto to_px = [&](double x, double y) {
    return Px{static_cast<int>(std::floor((x - map.origin_x) / res)),
              rows - 1 - static_cast<int>(std::floor((y - map.origin_y) / res))};
  };
  const auto centre = [](Px p) {
    return grid::Pixel{static_cast<double>(p.x), static_cast<double>(p.y)};
  };
  const int side = std::min(img.width(), img.height());
  // End points as squares of `ps` pixels, so that they show on big images.
  const int ps = std::max(1, side / 700);
  for (size_t k = 0; k < ov.points.size(); ++k) {
    const grid::Bgr c = group_colour(ov.group[k]);
    for (const Point2D& p : ov.points[k]) {
      const Px q = to_px(p.x, p.y);
      grid::fill_rect(img, q.x, q.y, q.x + ps - 1, q.y + ps - 1, c);
    }
  }
  const int dot = std::max(2, side / 300);
  for (size_t k = 1; k < ov.pose.size(); ++k)
    grid::draw_line(img, centre(to_px(ov.pose[k - 1].x, ov.pose[k - 1].y)),
                    centre(to_px(ov.pose[k].x, ov.pose[k].y)),
                    grid::Bgr::grey(90));
  for (size_t k = 0; k < ov.pose.size(); ++k) {
    const grid::Pixel q = centre(to_px(ov.pose[k].x, ov.pose[k].y));
    grid::fill_circle(img, q, dot, group_colour(ov.group[k]));
    grid::draw_circle(img, q, dot, grid::Bgr::grey(0));
  }
  // Labels last, so that no dot hides them; outlined in white, so that they
  // read over the map and the points.
  const int scale = grid::digit_scale(std::max(0.4, side / 1500.0));
  for (int g = 0; g < ov.groups; ++g) {
    double mx = 0, my = 0;
    int n = 0;
    for (size_t k = 0; k < ov.pose.size(); ++k)
      if (ov.group[k] == g) mx += ov.pose[k].x, my += ov.pose[k].y, ++n;
    if (n == 0) continue;
    mx /= n, my /= n;
    size_t best = 0;
    double bd = INFINITY;
    for (size_t k = 0; k < ov.pose.size(); ++k)
      if (ov.group[k] == g) {
        const double d = std::hypot(ov.pose[k].x - mx, ov.pose[k].y - my);
        if (d < bd) bd = d, best = k;
      }
    const Px at = to_px(ov.pose[best].x, ov.pose[best].y);
    const int x = at.x + dot + 2, y = at.y - dot - 2;
    const std::string text = std::to_string(g);
    for (int dy = -scale; dy <= scale; dy += scale)
      for (int dx = -scale; dx <= scale; dx += scale)
        grid::draw_digits(img, text, x + dx, y + dy, scale, grid::Bgr::grey(255));
    grid::draw_digits(img, text, x, y, scale, group_colour(g));
  }
  return img;
}

}  // namespace hmt::grouping

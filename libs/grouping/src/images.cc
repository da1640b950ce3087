#include "hmt/grouping/images.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>

namespace hmt::grouping {

cv::Vec3b group_colour(int group) {
  // Tableau-like palette, BGR.
  static const cv::Vec3b kPalette[] = {
      {180, 119, 31}, {14, 127, 255}, {44, 160, 44},  {40, 39, 214},
      {189, 103, 148}, {75, 86, 140}, {194, 119, 227}, {34, 189, 188},
      {207, 190, 23}, {0, 0, 128},    {128, 128, 0},  {60, 20, 220}};
  constexpr int kN = sizeof(kPalette) / sizeof(kPalette[0]);
  return kPalette[((group % kN) + kN) % kN];
}

cv::Mat weight_image(const area::WeightMatrix& W, const std::vector<int>& order,
                     const std::vector<int>& block_sizes, int target_px) {
  const int n = static_cast<int>(W.rows());
  if (W.cols() != n || static_cast<int>(order.size()) != n)
    throw std::invalid_argument("weight_image: order is not over W's nodes");
  if (n == 0) return cv::Mat(1, 1, CV_8UC3, cv::Scalar(0, 0, 0));
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
  cv::Mat grey(side, side, CV_8UC1, cv::Scalar(0));
  const auto paint = [&](int r, int c, double w) {
    const uint8_t v = static_cast<uint8_t>(
        std::lround(255.0 * std::clamp(w, 0.0, 1.0)));
    const int r0 = px(r), r1 = std::max(px(r + 1), r0 + 1);
    const int c0 = px(c), c1 = std::max(px(c + 1), c0 + 1);
    for (int y = r0; y < r1 && y < side; ++y) {
      uint8_t* row = grey.ptr<uint8_t>(y);
      for (int x = c0; x < c1 && x < side; ++x) row[x] = std::max(row[x], v);
    }
  };
  for (int c = 0; c < W.outerSize(); ++c)
    for (area::WeightMatrix::InnerIterator it(W, c); it; ++it)
      if (it.row() != c) paint(pos[it.row()], pos[c], it.value());
  for (int k = 0; k < n; ++k) paint(k, k, 1.0);

  cv::Mat img;
  cv::cvtColor(grey, img, cv::COLOR_GRAY2BGR);
  int start = 0;
  for (size_t g = 0; g < block_sizes.size(); ++g) {
    const int end = start + block_sizes[g];
    if (block_sizes[g] <= 0 || end > n)
      throw std::invalid_argument("weight_image: bad block sizes");
    const cv::Vec3b c = group_colour(static_cast<int>(g));
    const int thick = side >= 400 ? 2 : 1;
    cv::rectangle(img, cv::Point(px(start), px(start)),
                  cv::Point(std::max(px(end) - 1, px(start)),
                            std::max(px(end) - 1, px(start))),
                  cv::Scalar(c[0], c[1], c[2]), thick);
    start = end;
  }
  return img;
}

cv::Mat groups_map_image(const grid::MapImage& map, const MapOverlay& ov) {
  cv::Mat img;
  cv::cvtColor(map.image, img, cv::COLOR_GRAY2BGR);
  const double res = map.resolution;
  const int rows = img.rows;
  // Pixel of a map-frame point (row 0 is the top, the largest y).
  const auto to_px = [&](double x, double y) {
    return cv::Point(static_cast<int>(std::floor((x - map.origin_x) / res)),
                     rows - 1 - static_cast<int>(std::floor((y - map.origin_y) / res)));
  };
  const int side = std::min(img.cols, img.rows);
  // End points as squares of `ps` pixels, so that they show on big images.
  const int ps = std::max(1, side / 700);
  for (size_t k = 0; k < ov.points.size(); ++k) {
    const cv::Vec3b c = group_colour(ov.group[k]);
    for (const Point2D& p : ov.points[k]) {
      const cv::Point q = to_px(p.x, p.y);
      cv::rectangle(img, cv::Rect(q.x, q.y, ps, ps), cv::Scalar(c[0], c[1], c[2]),
                    cv::FILLED);
    }
  }
  const int dot = std::max(2, side / 300);
  for (size_t k = 1; k < ov.pose.size(); ++k)
    cv::line(img, to_px(ov.pose[k - 1].x, ov.pose[k - 1].y),
             to_px(ov.pose[k].x, ov.pose[k].y), cv::Scalar(90, 90, 90), 1,
             cv::LINE_AA);
  for (size_t k = 0; k < ov.pose.size(); ++k) {
    const cv::Vec3b c = group_colour(ov.group[k]);
    const cv::Point q = to_px(ov.pose[k].x, ov.pose[k].y);
    cv::circle(img, q, dot, cv::Scalar(c[0], c[1], c[2]), cv::FILLED,
               cv::LINE_AA);
    cv::circle(img, q, dot, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  }
  // Labels last, so that no dot hides them.
  const double font = std::max(0.4, side / 1500.0);
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
    const cv::Point q = to_px(ov.pose[best].x, ov.pose[best].y) +
                        cv::Point(dot + 2, -dot - 2);
    const std::string text = std::to_string(g);
    const cv::Vec3b c = group_colour(g);
    const int thick = std::max(1, static_cast<int>(std::lround(font * 1.5)));
    cv::putText(img, text, q, cv::FONT_HERSHEY_SIMPLEX, font,
                cv::Scalar(255, 255, 255), thick + 2, cv::LINE_AA);
    cv::putText(img, text, q, cv::FONT_HERSHEY_SIMPLEX, font,
                cv::Scalar(c[0], c[1], c[2]), thick, cv::LINE_AA);
  }
  return img;
}

}  // namespace hmt::grouping

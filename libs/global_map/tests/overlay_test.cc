#include "hmt/global_map/overlay.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <cstring>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>
#include <utility>

#include "hmt/common/error.h"
#include "hmt/grid/png.h"
#include "hmt_test/scratch.h"

namespace hmt::global_map {
namespace {

using grid::Bgr;
using grid::Image;
using topology::HmtMap;
using topology::PoseGaussian;

constexpr uint8_t kGrey = 205;

// A blank 6 m x 5 m map image at 5 cm, its lower-left corner at (-1, -2).
grid::MapImage blank_base() {
  grid::MapImage base;
  base.image = Image(120, 100, 1, kGrey);
  base.resolution = 0.05;
  base.origin_x = -1.0;
  base.origin_y = -2.0;
  return base;
}

// Root 0 at the origin; area 1 at (2, 0.5) with a position covariance
// stretched along x (standard deviations 0.1 m and 0.05 m).
struct Scene {
  HmtMap map;
  GlobalPoses poses;
};

Scene two_areas() {
  Scene s;
  s.map.add_area(0);
  s.map.add_area(1);
  Eigen::Matrix3d cov = Eigen::Vector3d(0.01, 0.0025, 0.01).asDiagonal();
  s.map.add_arc_measurement(0, 1, PoseGaussian(Pose2D(2, 0.5, 0), cov));
  s.poses.root = 0;
  s.poses.poses.emplace(0, PoseGaussian(Pose2D()));
  s.poses.poses.emplace(1, PoseGaussian(Pose2D(2, 0.5, 0), cov));
  return s;
}

// (column, row) of the pixel nearest to a map-frame point.
using Px = std::pair<int, int>;
Px nearest_pixel(const grid::MapImage& base, const Point2D& p) {
  const grid::Pixel q = pixel_of(base, p);
  return {static_cast<int>(std::lround(q.x)), static_cast<int>(std::lround(q.y))};
}

Bgr at(const Image& image, Px p) { return image.bgr(p.first, p.second); }

bool is_grey(const Bgr& v) { return v.b == v.g && v.g == v.r; }

// Largest horizontal and vertical pixel distance from `centre` of the
// pixels painted exactly in `colour`.
Px extent_of(const Image& image, const Bgr& colour, Px centre) {
  Px extent(0, 0);
  for (int r = 0; r < image.height(); ++r)
    for (int col = 0; col < image.width(); ++col)
      if (image.bgr(col, r) == colour) {
        extent.first = std::max(extent.first, std::abs(col - centre.first));
        extent.second = std::max(extent.second, std::abs(r - centre.second));
      }
  return extent;
}

TEST(Overlay, PixelOfFollowsTheMapImageConvention) {
  const grid::MapImage base = blank_base();
  // The centre of the lower-left pixel is (0, rows - 1).
  const grid::Pixel p = pixel_of(base, {-1.0 + 0.025, -2.0 + 0.025});
  EXPECT_NEAR(p.x, 0.0, 1e-9);
  EXPECT_NEAR(p.y, 99.0, 1e-9);
  // y grows upwards, rows downwards.
  EXPECT_NEAR(pixel_of(base, {0.0, 0.0}).y - pixel_of(base, {0.0, 1.0}).y,
              20.0, 1e-9);
}

TEST(Overlay, DrawsAreasAndArcsInColourOverTheGreyMap) {
  const grid::MapImage base = blank_base();
  const Scene s = two_areas();
  const OverlayOptions options;
  const Image out = draw_topology_overlay(base, s.map, s.poses, options);
  EXPECT_EQ(out.channels(), 3);
  EXPECT_EQ(out.width(), base.image.width());
  EXPECT_EQ(out.height(), base.image.height());
  for (AreaId id : {0u, 1u}) {
    const Pose2D& p = s.poses.poses.at(id).mean;
    EXPECT_EQ(at(out, nearest_pixel(base, {p.x, p.y})), options.origin_colour)
        << "area " << id;
  }
  // Along the arc, between the root's dot and area 1's ellipse: in every
  // column, the pixel nearest to the segment.
  const grid::Pixel p0 = pixel_of(base, {0.0, 0.0}), p1 = pixel_of(base, {2.0, 0.5});
  for (int col = 24; col <= 34; ++col) {
    const double row = p0.y + (col - p0.x) * (p1.y - p0.y) / (p1.x - p0.x);
    EXPECT_EQ(out.bgr(col, static_cast<int>(std::floor(row + 0.5))), options.arc_colour)
        << "column " << col;
  }
  // The map away from the drawing is untouched.
  EXPECT_EQ(out.bgr(0, 0), Bgr::grey(kGrey));
  EXPECT_EQ(out.bgr(119, 99), Bgr::grey(kGrey));
  // The labels, "0" and "1", in their colour up and right of the origins.
  for (AreaId id : {0u, 1u}) {
    const Px o = nearest_pixel(base, {s.poses.poses.at(id).mean.x,
                                      s.poses.poses.at(id).mean.y});
    int n = 0;
    for (int dy = -20; dy <= 0; ++dy)
      for (int dx = 0; dx <= 20; ++dx)
        if (o.first + dx < out.width() && o.second + dy >= 0 &&
            out.bgr(o.first + dx, o.second + dy) == options.label_colour)
          ++n;
    EXPECT_GE(n, 7) << "label of area " << id;
  }
  int off_grey = 0;
  for (int r = 0; r < out.height(); ++r)
    for (int c = 0; c < out.width(); ++c) off_grey += !is_grey(out.bgr(c, r));
  EXPECT_GT(off_grey, 0);
}

TEST(Overlay, EllipseGrowsWithTheScaleAndFollowsTheCovariance) {
  const grid::MapImage base = blank_base();
  const Scene s = two_areas();
  const Px centre = nearest_pixel(base, {2.0, 0.5});
  OverlayOptions options;
  options.draw_labels = false;
  // Semi-axes of the 95% ellipse: sqrt(5.991) * (0.1, 0.05) m, i.e. 4.9 and
  // 2.4 pixels, times the scale.
  options.ellipse_scale = 1.0;
  const Px small = extent_of(
      draw_topology_overlay(base, s.map, s.poses, options),
      options.ellipse_colour, centre);
  options.ellipse_scale = 5.0;
  const Px large = extent_of(
      draw_topology_overlay(base, s.map, s.poses, options),
      options.ellipse_colour, centre);
  EXPECT_NEAR(small.first, 4.9, 1.0);
  EXPECT_NEAR(large.first, 24.5, 1.0);
  EXPECT_NEAR(large.second, 12.2, 1.0);
  // The root is known exactly: no ellipse of its own, so nothing coloured
  // that way near it.
  const Image out = draw_topology_overlay(base, s.map, s.poses, options);
  const Px root = nearest_pixel(base, {0.0, 0.0});
  const Bgr ellipse{0, 160, 0};
  for (int dr = -6; dr <= 6; ++dr)
    for (int dc = -6; dc <= 6; ++dc)
      EXPECT_NE(out.bgr(root.first + dc, root.second + dr), ellipse);
  options.ellipse_scale = 0.0;
  EXPECT_EQ(extent_of(draw_topology_overlay(base, s.map, s.poses, options),
                      options.ellipse_colour, centre),
            Px(0, 0));
}

TEST(Overlay, RejectsBadInput) {
  const Scene s = two_areas();
  grid::MapImage colour = blank_base();
  colour.image = grid::grey_to_bgr(colour.image);
  EXPECT_THROW(draw_topology_overlay(colour, s.map, s.poses),
               std::invalid_argument);
  grid::MapImage unscaled = blank_base();
  unscaled.resolution = 0.0;
  EXPECT_THROW(draw_topology_overlay(unscaled, s.map, s.poses),
               std::invalid_argument);
  OverlayOptions options;
  options.ellipse_scale = -1.0;
  EXPECT_THROW(draw_topology_overlay(blank_base(), s.map, s.poses, options),
               std::invalid_argument);
}

TEST(Overlay, WriteColorPngRoundTripsAndFailsCleanly) {
  const grid::MapImage base = blank_base();
  const Scene s = two_areas();
  const Image out = draw_topology_overlay(base, s.map, s.poses);
  const std::string dir = scratch::folder("overlay").string();
  write_color_png(out, dir + "/overlay.png");
  const cv::Mat back = cv::imread(dir + "/overlay.png", cv::IMREAD_COLOR);
  ASSERT_FALSE(back.empty());
  ASSERT_EQ(back.cols, out.width());
  ASSERT_EQ(back.rows, out.height());
  for (int r = 0; r < out.height(); ++r)
    ASSERT_EQ(std::memcmp(back.ptr<uint8_t>(r), out.row(r),
                          static_cast<size_t>(out.width()) * 3),
              0)
        << "row " << r;
  EXPECT_THROW(write_color_png(out, dir + "/missing/overlay.png"), OutputError);
  EXPECT_FALSE(std::filesystem::exists(dir + "/missing"));
  EXPECT_THROW(write_color_png(Image(), dir + "/empty.png"), OutputError);
  EXPECT_FALSE(std::filesystem::exists(dir + "/empty.png"));
}

TEST(Overlay, StreamedBandByBandItIsTheWholeImage) {
  // A grid with walls, the two areas drawn over it, and an area whose label
  // and ellipse straddle band boundaries: the PNG written band by band is
  // byte for byte the one of the whole image.
  grid::OccupancyGrid g(0.02);
  for (int x = -60; x < 160; ++x) {
    g.mutable_logodds({x, -90}) = 100;
    g.mutable_logodds({x, 300}) = 100;
    for (int y = -89; y < 300; y += 7) g.mutable_logodds({x, y}) = -60;
  }
  Scene s = two_areas();
  s.map.add_area(2);
  const Eigen::Matrix3d cov = Eigen::Vector3d(0.04, 0.01, 0.01).asDiagonal();
  s.map.add_arc_measurement(1, 2, PoseGaussian(Pose2D(0.5, 4.6, 0.3), cov));
  s.poses.poses.emplace(2, PoseGaussian(Pose2D(2.5, 5.12, 0.3), cov));
  const grid::MapImage base = grid::render(g, 10);
  ASSERT_GT(base.image.height(), 256);  // more than one band
  const std::string dir = scratch::folder("overlay_stream").string();
  write_color_png(draw_topology_overlay(base, s.map, s.poses), dir + "/whole.png");
  TopologyOverlayRows rows(g, grid::map_frame(g, 10), s.map, s.poses);
  grid::write_png_file(rows, dir + "/streamed.png");
  auto bytes = [](const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(f)), {});
  };
  const std::string whole = bytes(dir + "/whole.png");
  EXPECT_GT(whole.size(), 100u);
  EXPECT_EQ(whole, bytes(dir + "/streamed.png"));
}

}  // namespace
}  // namespace hmt::global_map

#include "hmt/global_map/overlay.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "hmt/common/error.h"

namespace hmt::global_map {
namespace {

using topology::HmtMap;
using topology::PoseGaussian;

constexpr uint8_t kGrey = 205;

// A blank 6 m x 5 m map image at 5 cm, its lower-left corner at (-1, -2).
grid::MapImage blank_base() {
  grid::MapImage base;
  base.image = cv::Mat(100, 120, CV_8UC1, cv::Scalar(kGrey));
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

cv::Point nearest_pixel(const grid::MapImage& base, const Point2D& p) {
  const cv::Point2d q = pixel_of(base, p);
  return {static_cast<int>(std::lround(q.x)), static_cast<int>(std::lround(q.y))};
}

bool is_grey(const cv::Vec3b& v) { return v[0] == v[1] && v[1] == v[2]; }

// Largest horizontal and vertical pixel distance from `centre` of the
// pixels painted exactly in `colour`.
cv::Point2i extent_of(const cv::Mat& image, const cv::Scalar& colour,
                      const cv::Point& centre) {
  const cv::Vec3b c(static_cast<uchar>(colour[0]), static_cast<uchar>(colour[1]),
                    static_cast<uchar>(colour[2]));
  cv::Point2i extent(0, 0);
  for (int r = 0; r < image.rows; ++r)
    for (int col = 0; col < image.cols; ++col)
      if (image.at<cv::Vec3b>(r, col) == c) {
        extent.x = std::max(extent.x, std::abs(col - centre.x));
        extent.y = std::max(extent.y, std::abs(r - centre.y));
      }
  return extent;
}

TEST(Overlay, PixelOfFollowsTheMapImageConvention) {
  const grid::MapImage base = blank_base();
  // The centre of the lower-left pixel is (0, rows - 1).
  const cv::Point2d p = pixel_of(base, {-1.0 + 0.025, -2.0 + 0.025});
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
  const cv::Mat out = draw_topology_overlay(base, s.map, s.poses, options);
  EXPECT_EQ(out.type(), CV_8UC3);
  EXPECT_EQ(out.size(), base.image.size());
  for (AreaId id : {0u, 1u}) {
    const Pose2D& p = s.poses.poses.at(id).mean;
    const cv::Vec3b at = out.at<cv::Vec3b>(nearest_pixel(base, {p.x, p.y}));
    EXPECT_FALSE(is_grey(at)) << "area " << id;
  }
  // Half-way along the arc.
  const cv::Vec3b mid = out.at<cv::Vec3b>(nearest_pixel(base, {1.0, 0.25}));
  EXPECT_EQ(mid, cv::Vec3b(200, 120, 0));
  // The map away from the drawing is untouched.
  EXPECT_EQ(out.at<cv::Vec3b>(0, 0), cv::Vec3b(kGrey, kGrey, kGrey));
  EXPECT_EQ(out.at<cv::Vec3b>(99, 119), cv::Vec3b(kGrey, kGrey, kGrey));
}

TEST(Overlay, EllipseGrowsWithTheScaleAndFollowsTheCovariance) {
  const grid::MapImage base = blank_base();
  const Scene s = two_areas();
  const cv::Point centre = nearest_pixel(base, {2.0, 0.5});
  OverlayOptions options;
  options.draw_labels = false;
  // Semi-axes of the 95% ellipse: sqrt(5.991) * (0.1, 0.05) m, i.e. 4.9 and
  // 2.4 pixels, times the scale.
  options.ellipse_scale = 1.0;
  const cv::Point2i small = extent_of(
      draw_topology_overlay(base, s.map, s.poses, options),
      options.ellipse_colour, centre);
  options.ellipse_scale = 5.0;
  const cv::Point2i large = extent_of(
      draw_topology_overlay(base, s.map, s.poses, options),
      options.ellipse_colour, centre);
  EXPECT_NEAR(small.x, 4.9, 1.0);
  EXPECT_NEAR(large.x, 24.5, 1.0);
  EXPECT_NEAR(large.y, 12.2, 1.0);
  // The root is known exactly: no ellipse of its own, so nothing coloured
  // that way near it.
  const cv::Mat out = draw_topology_overlay(base, s.map, s.poses, options);
  const cv::Point root = nearest_pixel(base, {0.0, 0.0});
  const cv::Vec3b ellipse(0, 160, 0);
  for (int dr = -6; dr <= 6; ++dr)
    for (int dc = -6; dc <= 6; ++dc)
      EXPECT_NE(out.at<cv::Vec3b>(root.y + dr, root.x + dc), ellipse);
  options.ellipse_scale = 0.0;
  EXPECT_EQ(extent_of(draw_topology_overlay(base, s.map, s.poses, options),
                      options.ellipse_colour, centre),
            cv::Point2i(0, 0));
}

TEST(Overlay, RejectsBadInput) {
  const Scene s = two_areas();
  grid::MapImage colour = blank_base();
  cv::cvtColor(colour.image, colour.image, cv::COLOR_GRAY2BGR);
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
  const cv::Mat out = draw_topology_overlay(base, s.map, s.poses);
  const std::string dir = testing::TempDir() + "/hmt_overlay";
  std::filesystem::create_directories(dir);
  write_color_png(out, dir + "/overlay.png");
  const cv::Mat back = cv::imread(dir + "/overlay.png", cv::IMREAD_COLOR);
  ASSERT_FALSE(back.empty());
  EXPECT_EQ(cv::norm(out, back, cv::NORM_INF), 0.0);
  EXPECT_THROW(write_color_png(out, dir + "/missing/overlay.png"), OutputError);
  EXPECT_FALSE(std::filesystem::exists(dir + "/missing"));
  EXPECT_THROW(write_color_png(cv::Mat(), dir + "/empty.png"), OutputError);
  EXPECT_FALSE(std::filesystem::exists(dir + "/empty.png"));
}

}  // namespace
}  // namespace hmt::global_map

#include "hmt/global_map/overlay.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>

#include "hmt/grid/png.h"

namespace hmt::global_map {
namespace {

// Drawing coordinates carry this many fractional bits (OpenCV's `shift`),
// so an origin or an ellipse is placed to 1/16 pixel rather than rounded.
constexpr int kShift = 4;
constexpr double kSubpixel = 1 << kShift;

void require_valid(const grid::MapImage& base, const OverlayOptions& o) {
  if (base.image.empty() || base.image.type() != CV_8UC1)
    throw std::invalid_argument(
        "draw_topology_overlay: the base must be a non-empty CV_8UC1 image");
  if (!(base.resolution > 0.0) || !std::isfinite(base.resolution))
    throw std::invalid_argument(
        "draw_topology_overlay: the base resolution must be positive");
  if (!(o.ellipse_scale >= 0.0) || !std::isfinite(o.ellipse_scale))
    throw std::invalid_argument(
        "draw_topology_overlay: ellipse_scale must be >= 0 and finite");
  if (o.origin_radius_px < 1 || o.line_thickness_px < 1)
    throw std::invalid_argument(
        "draw_topology_overlay: origin radius and line thickness must be >= 1");
  if (!(o.font_scale > 0.0))
    throw std::invalid_argument("draw_topology_overlay: font_scale must be > 0");
}

cv::Point fixed_point(const cv::Point2d& p) {
  return {static_cast<int>(std::lround(p.x * kSubpixel)),
          static_cast<int>(std::lround(p.y * kSubpixel))};
}

int fixed_length(double pixels) {
  return static_cast<int>(std::lround(pixels * kSubpixel));
}

cv::Point2d origin_pixel(const grid::MapImage& base,
                         const topology::PoseGaussian& pose) {
  return pixel_of(base, {pose.mean.x, pose.mean.y});
}

void draw_arcs(cv::Mat& image, const grid::MapImage& base,
               const topology::HmtMap& map, const GlobalPoses& poses,
               const OverlayOptions& o) {
  for (const auto& [ends, arc] : map.arcs()) {
    const auto a = poses.poses.find(ends.first);
    const auto b = poses.poses.find(ends.second);
    if (a == poses.poses.end() || b == poses.poses.end()) continue;
    cv::line(image, fixed_point(origin_pixel(base, a->second)),
             fixed_point(origin_pixel(base, b->second)), o.arc_colour,
             o.line_thickness_px, cv::LINE_8, kShift);
  }
}

// The 95% ellipse of the position block, magnified. In the image the y axis
// points down, so an eigenvector (v_x, v_y) of the map frame is at angle
// atan2(-v_y, v_x) there (OpenCV's ellipse angle, in degrees).
void draw_ellipse(cv::Mat& image, const grid::MapImage& base,
                  const topology::PoseGaussian& pose, const OverlayOptions& o) {
  const Eigen::Matrix2d cov = pose.cov.topLeftCorner<2, 2>();
  if (!cov.allFinite()) return;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
  const Eigen::Vector2d lambda = eig.eigenvalues();  // ascending
  if (!(lambda(1) > 0.0)) return;  // known exactly (the root)
  const double k = o.ellipse_scale * std::sqrt(kChi2TwoDof95) / base.resolution;
  const double major = k * std::sqrt(lambda(1));
  const double minor = k * std::sqrt(std::max(lambda(0), 0.0));
  const Eigen::Vector2d v = eig.eigenvectors().col(1);
  const double angle = std::atan2(-v.y(), v.x()) * 180.0 / M_PI;
  cv::ellipse(image, fixed_point(origin_pixel(base, pose)),
              cv::Size(fixed_length(major), fixed_length(minor)), angle, 0.0,
              360.0, o.ellipse_colour, o.line_thickness_px, cv::LINE_8, kShift);
}

void draw_label(cv::Mat& image, const grid::MapImage& base, AreaId id,
                const topology::PoseGaussian& pose, const OverlayOptions& o) {
  const cv::Point2d at = origin_pixel(base, pose);
  const int gap = o.origin_radius_px + 2;  // up and right, clear of the dot
  cv::putText(image, std::to_string(id),
              cv::Point(static_cast<int>(std::lround(at.x)) + gap,
                        static_cast<int>(std::lround(at.y)) - gap),
              cv::FONT_HERSHEY_SIMPLEX, o.font_scale, o.label_colour, 1,
              cv::LINE_8);
}

}  // namespace

cv::Point2d pixel_of(const grid::MapImage& base, const Point2D& p) {
  // Pixel column c covers x in [origin_x + c res, origin_x + (c + 1) res);
  // row r covers the (rows - 1 - r)-th band of y from origin_y.
  const double col = (p.x - base.origin_x) / base.resolution - 0.5;
  const double row =
      base.image.rows - (p.y - base.origin_y) / base.resolution - 0.5;
  return {col, row};
}

cv::Mat draw_topology_overlay(const grid::MapImage& base,
                              const topology::HmtMap& map,
                              const GlobalPoses& poses,
                              const OverlayOptions& options) {
  require_valid(base, options);
  cv::Mat image;
  cv::cvtColor(base.image, image, cv::COLOR_GRAY2BGR);
  draw_arcs(image, base, map, poses, options);
  if (options.ellipse_scale > 0.0)
    for (const auto& [id, pose] : poses.poses)
      draw_ellipse(image, base, pose, options);
  if (options.draw_labels)
    for (const auto& [id, pose] : poses.poses)
      draw_label(image, base, id, pose, options);
  for (const auto& [id, pose] : poses.poses)
    cv::circle(image, fixed_point(origin_pixel(base, pose)),
               fixed_length(options.origin_radius_px), options.origin_colour,
               cv::FILLED, cv::LINE_8, kShift);
  return image;
}

void write_color_png(const cv::Mat& image, const std::string& path) {
  grid::write_png_file(image, path);
}

}  // namespace hmt::global_map

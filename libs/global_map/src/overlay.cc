#include "hmt/global_map/overlay.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "hmt/grid/png.h"

namespace hmt::global_map {
namespace {

void require_valid(const grid::MapFrame& base, const OverlayOptions& o) {
  if (base.width <= 0 || base.height <= 0)
    throw std::invalid_argument(
        "draw_topology_overlay: the base must be a non-empty grey image");
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

// Origins stay at their exact (sub-pixel) place: the drawing functions take
// continuous coordinates.
grid::Pixel origin_pixel(const grid::MapFrame& base,
                         const topology::PoseGaussian& pose) {
  return pixel_of(base, {pose.mean.x, pose.mean.y});
}

void draw_arcs(grid::Image& image, const grid::MapFrame& base,
               const topology::HmtMap& map, const GlobalPoses& poses,
               const OverlayOptions& o) {
  for (const auto& [ends, arc] : map.arcs()) {
    const auto a = poses.poses.find(ends.first);
    const auto b = poses.poses.find(ends.second);
    if (a == poses.poses.end() || b == poses.poses.end()) continue;
    grid::draw_line(image, origin_pixel(base, a->second),
                    origin_pixel(base, b->second), o.arc_colour,
                    o.line_thickness_px);
  }
}

// The 95% ellipse of the position block, magnified. In the image the y axis
// points down, so an eigenvector (v_x, v_y) of the map frame is at angle
// atan2(-v_y, v_x) there.
void draw_ellipse(grid::Image& image, const grid::MapFrame& base,
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
  grid::draw_ellipse(image, origin_pixel(base, pose), major, minor,
                     std::atan2(-v.y(), v.x()), o.ellipse_colour,
                     o.line_thickness_px);
}

void draw_label(grid::Image& image, const grid::MapFrame& base, AreaId id,
                const topology::PoseGaussian& pose, const OverlayOptions& o) {
  const grid::Pixel at = origin_pixel(base, pose);
  if (!std::isfinite(at.x) || !std::isfinite(at.y)) return;
  // Up and right, clear of the dot; clamped so that the int conversion is
  // defined (draw_digits clips what falls outside).
  const double limit = 1e9;
  const int gap = o.origin_radius_px + 2;
  grid::draw_digits(image, std::to_string(id),
                    static_cast<int>(std::clamp(std::round(at.x), -limit, limit)) + gap,
                    static_cast<int>(std::clamp(std::round(at.y), -limit, limit)) - gap,
                    grid::digit_scale(o.font_scale), o.label_colour);
}

// Everything over the map, on the whole image or on a band of it.
void draw_overlay(grid::Image& image, const grid::MapFrame& base,
                  const topology::HmtMap& map, const GlobalPoses& poses,
                  const OverlayOptions& options) {
  draw_arcs(image, base, map, poses, options);
  if (options.ellipse_scale > 0.0)
    for (const auto& [id, pose] : poses.poses)
      draw_ellipse(image, base, pose, options);
  if (options.draw_labels)
    for (const auto& [id, pose] : poses.poses)
      draw_label(image, base, id, pose, options);
  for (const auto& [id, pose] : poses.poses)
    grid::fill_circle(image, origin_pixel(base, pose), options.origin_radius_px,
                      options.origin_colour);
}

// Rows per band of TopologyOverlayRows: a few megabytes in colour.
constexpr int kBandRows = 256;

}  // namespace

grid::Pixel pixel_of(const grid::MapFrame& base, const Point2D& p) {
  // Pixel column c covers x in [origin_x + c res, origin_x + (c + 1) res);
  // row r covers the (rows - 1 - r)-th band of y from origin_y.
  const double col = (p.x - base.origin_x) / base.resolution - 0.5;
  const double row = base.height - (p.y - base.origin_y) / base.resolution - 0.5;
  return {col, row};
}

grid::Pixel pixel_of(const grid::MapImage& base, const Point2D& p) {
  return pixel_of(base.frame(), p);
}

grid::Image draw_topology_overlay(const grid::MapImage& base,
                                  const topology::HmtMap& map,
                                  const GlobalPoses& poses,
                                  const OverlayOptions& options) {
  if (base.image.channels() != 1)
    throw std::invalid_argument("draw_topology_overlay: the base must be a grey image");
  require_valid(base.frame(), options);
  grid::Image image = grid::grey_to_bgr(base.image);
  draw_overlay(image, base.frame(), map, poses, options);
  return image;
}

TopologyOverlayRows::TopologyOverlayRows(const grid::OccupancyGrid& grid,
                                         const grid::MapFrame& frame,
                                         const topology::HmtMap& map,
                                         const GlobalPoses& poses,
                                         const OverlayOptions& options)
    : BandRows(frame.width, frame.height, 3, kBandRows),
      grid_(grid),
      frame_(frame),
      map_(map),
      poses_(poses),
      options_(options) {
  require_valid(frame, options);
}

grid::Image TopologyOverlayRows::make_band(int first_row, int rows) {
  grid::Image band = grid::grey_to_bgr(grid::render_band(grid_, frame_, first_row, rows));
  draw_overlay(band, frame_, map_, poses_, options_);
  return band;
}

void write_color_png(const grid::Image& image, const std::string& path) {
  grid::write_png_file(image, path);
}

}  // namespace hmt::global_map

// The topology drawn over a global map image (002 Fig. 7 and 9(d)): arcs as
// lines between the areas' origins, each origin as a dot labelled with its
// id, and the 95% confidence ellipse of each origin's position, magnified so
// that it can be seen at map scale.
#pragma once

#include <string>

#include "hmt/global_map/global_poses.h"
#include "hmt/grid/draw.h"
#include "hmt/grid/image.h"
#include "hmt/grid/map_export.h"
#include "hmt/topology/hmt_map.h"

namespace hmt::global_map {

// The 95% quantile of the chi-square distribution with 2 degrees of freedom:
// a 2D Gaussian puts 95% of its mass inside d^T Sigma^-1 d <= 5.991.
constexpr double kChi2TwoDof95 = 5.991;

struct OverlayOptions {
  // Magnification of the ellipses' semi-axes (>= 0; 0 draws none). The
  // paper's figures magnify them 5 times.
  double ellipse_scale = 5.0;
  int origin_radius_px = 3;  // >= 1
  int line_thickness_px = 1;  // >= 1
  // > 0: the labels' size as OpenCV's Hershey fonts measure it, digits about
  // 21 * font_scale pixels tall, drawn with grid::draw_digits at
  // grid::digit_scale(font_scale) (7 pixels tall up to 0.5).
  double font_scale = 0.4;
  bool draw_labels = true;
  grid::Bgr arc_colour{200, 120, 0};
  grid::Bgr ellipse_colour{0, 160, 0};
  grid::Bgr origin_colour{0, 0, 220};
  grid::Bgr label_colour{120, 0, 120};
};

// Continuous pixel coordinates (column, row) of a map-frame point on the
// image, integers at pixel centres; row 0 is the top (largest y).
grid::Pixel pixel_of(const grid::MapFrame& base, const Point2D& p);
grid::Pixel pixel_of(const grid::MapImage& base, const Point2D& p);

// A BGR copy of `base` (its grey levels in all three channels) with the
// arcs of `map` whose two ends are in `poses`, then the ellipses, labels and
// origins of the areas in `poses`, drawn in that order (so an origin's dot is
// never covered). The ellipse uses the 2x2 position block of the area's
// covariance: semi-axes ellipse_scale * sqrt(5.991 lambda_i) along its
// eigenvectors; the root, known exactly, has none. Throws
// std::invalid_argument for a base that is not a non-empty grey image with a
// positive resolution, or for bad options.
grid::Image draw_topology_overlay(const grid::MapImage& base,
                                  const topology::HmtMap& map,
                                  const GlobalPoses& poses,
                                  const OverlayOptions& options = {});

// draw_topology_overlay(grid::render(grid), ...) made band by band as it is
// written (grid::write_png_file(RowSource&, ...)): the same pixels, without
// holding the colour image whole, which for a large map is three times the
// size of its grey one. `frame` is grid::map_frame(grid, margin); the grid,
// map and poses must outlive the source. Throws std::invalid_argument as
// draw_topology_overlay does.
class TopologyOverlayRows : public grid::BandRows {
 public:
  TopologyOverlayRows(const grid::OccupancyGrid& grid, const grid::MapFrame& frame,
                      const topology::HmtMap& map, const GlobalPoses& poses,
                      const OverlayOptions& options = {});

 protected:
  grid::Image make_band(int first_row, int rows) override;

 private:
  const grid::OccupancyGrid& grid_;
  grid::MapFrame frame_;
  const topology::HmtMap& map_;
  const GlobalPoses& poses_;
  OverlayOptions options_;
};

// Writes a grey or BGR image as PNG, atomically (complete or absent, see
// hmt/common/files.h; grid::write_png_file). Throws hmt::OutputError on
// failure, including an empty image.
void write_color_png(const grid::Image& image, const std::string& path);

}  // namespace hmt::global_map

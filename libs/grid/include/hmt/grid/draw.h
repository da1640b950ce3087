// Drawing on colour images: what the pictures of maps need (topology over a
// map, groups, the weight matrix) and no more: lines, ellipses, circles,
// rectangles and numbers. Our own rather than OpenCV's imgproc, whose
// libraries (with their LAPACK, BLAS, TBB and X11 chain) cost every run
// several megabytes of resident memory for a few shapes.
//
// Every function draws on a 3-channel (BGR) image, throwing
// std::invalid_argument for another, and clips: a shape partly or wholly
// outside the image draws only its part inside, never writing out of bounds.
// On a band (hmt/grid/image.h) the part inside is its rows: drawing every
// band of an image paints the pixels that drawing the whole image would.
// Geometry that is not finite (a point at infinity, NaN) draws nothing.
// Nothing is anti-aliased: a pixel is painted in the colour or left alone.
#pragma once

#include <string>

#include "hmt/grid/image.h"

namespace hmt::grid {

// Continuous pixel coordinates (column, row), integers at pixel centres, so
// shapes can be placed between pixels.
struct Pixel {
  double x = 0.0;
  double y = 0.0;
};

// The pixels from (x0, y0) to (x1, y1), both corners included, in any order.
void fill_rect(Image& image, int x0, int y0, int x1, int y1, Bgr colour);

// The outline of that rectangle, each side a band `thickness` pixels wide
// centred on it (>= 1, else std::invalid_argument).
void draw_rect(Image& image, int x0, int y0, int x1, int y1, Bgr colour,
               int thickness = 1);

// The segment from a to b. Thickness 1 paints one pixel per step along the
// longer axis (an 8-connected line, as Bresenham's); a thicker one paints the
// pixels within thickness / 2 of the segment, round at the ends. thickness
// >= 1, else std::invalid_argument.
void draw_line(Image& image, Pixel a, Pixel b, Bgr colour, int thickness = 1);

// The pixels whose centre is within `radius` (>= 0, else
// std::invalid_argument) of `centre`.
void fill_circle(Image& image, Pixel centre, double radius, Bgr colour);

// The outline of an ellipse with semi-axis `semi_a` along the direction at
// `angle` radians from the x axis (towards +y, i.e. clockwise on the image,
// whose rows go down) and `semi_b` across it (both >= 0, thickness >= 1,
// else std::invalid_argument), as a closed polygon of short segments.
void draw_ellipse(Image& image, Pixel centre, double semi_a, double semi_b,
                  double angle, Bgr colour, int thickness = 1);

// A circle's outline: draw_ellipse with equal semi-axes.
void draw_circle(Image& image, Pixel centre, double radius, Bgr colour,
                 int thickness = 1);

// Numbers in a 5 x 7 pixel font, each font pixel a square of `scale` (>= 1,
// else std::invalid_argument) image pixels, characters 6 font pixels apart.
// The labels are ids, so the font has the digits and '-' only; any other
// character is left blank. (x, y) is the bottom-left pixel of the text, as
// for a baseline.
constexpr int kGlyphWidth = 5;
constexpr int kGlyphHeight = 7;
constexpr int kGlyphAdvance = 6;
void draw_digits(Image& image, const std::string& text, int x, int y,
                 int scale, Bgr colour);

// The integer scale at which draw_digits' digits are about as tall as those
// of OpenCV's Hershey fonts at `font_scale` (21 pixels at 1.0), at least 1.
int digit_scale(double font_scale);

}  // namespace hmt::grid

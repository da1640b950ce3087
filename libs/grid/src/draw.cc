#include "hmt/grid/draw.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace hmt::grid {
namespace {

void require_colour(const Image& image, const char* what) {
  if (image.channels() != 3)
    throw std::invalid_argument(std::string(what) +
                                ": drawing needs a 3-channel (BGR) image");
}

void require_thickness(int thickness, const char* what) {
  if (thickness < 1)
    throw std::invalid_argument(std::string(what) + ": thickness must be >= 1");
}

bool finite(Pixel p) { return std::isfinite(p.x) && std::isfinite(p.y); }

void put(Image& image, int x, int y, Bgr c) {
  uint8_t* p = &image.at(x, y);
  p[0] = c.b;
  p[1] = c.g;
  p[2] = c.r;
}

// Paints row y from x0 to x1 (included; finite doubles, any size) clipped
// to the image. Clamping happens in doubles, before any conversion to int.
void span(Image& image, int y, double x0, double x1, Bgr c) {
  if (y < image.first_row() || y >= image.end_row()) return;
  x0 = std::max(x0, 0.0);
  x1 = std::min(x1, image.width() - 1.0);
  if (!(x0 <= x1)) return;  // also NaN
  for (int x = static_cast<int>(x0); x <= static_cast<int>(x1); ++x) put(image, x, y, c);
}

// As span(), down column x.
void column_span(Image& image, int x, double y0, double y1, Bgr c) {
  if (x < 0 || x >= image.width()) return;
  y0 = std::max(y0, static_cast<double>(image.first_row()));
  y1 = std::min(y1, image.end_row() - 1.0);
  if (!(y0 <= y1)) return;  // also NaN
  for (int y = static_cast<int>(y0); y <= static_cast<int>(y1); ++y) put(image, x, y, c);
}

// The 5 x 7 glyphs, one row a byte, the leftmost pixel the highest of the 5
// bits.
constexpr uint8_t kDigits[10][kGlyphHeight] = {
    {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E},  // 0
    {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E},  // 1
    {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F},  // 2
    {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E},  // 3
    {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02},  // 4
    {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E},  // 5
    {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E},  // 6
    {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08},  // 7
    {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E},  // 8
    {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C},  // 9
};
constexpr uint8_t kMinus[kGlyphHeight] = {0, 0, 0, 0x1F, 0, 0, 0};

const uint8_t* glyph(char ch) {
  if (ch >= '0' && ch <= '9') return kDigits[ch - '0'];
  if (ch == '-') return kMinus;
  return nullptr;
}

}  // namespace

void fill_rect(Image& image, int x0, int y0, int x1, int y1, Bgr colour) {
  require_colour(image, "fill_rect");
  if (x0 > x1) std::swap(x0, x1);
  if (y0 > y1) std::swap(y0, y1);
  for (int y = std::max(y0, image.first_row()); y <= std::min(y1, image.end_row() - 1); ++y)
    span(image, y, x0, x1, colour);
}

void draw_rect(Image& image, int x0, int y0, int x1, int y1, Bgr colour,
               int thickness) {
  require_colour(image, "draw_rect");
  require_thickness(thickness, "draw_rect");
  if (x0 > x1) std::swap(x0, x1);
  if (y0 > y1) std::swap(y0, y1);
  // A band of `thickness` pixels around each side, as a thick line on it.
  const int before = (thickness - 1) / 2, after = thickness - 1 - before;
  fill_rect(image, x0 - before, y0 - before, x1 + after, y0 + after, colour);
  fill_rect(image, x0 - before, y1 - before, x1 + after, y1 + after, colour);
  fill_rect(image, x0 - before, y0 - before, x0 + after, y1 + after, colour);
  fill_rect(image, x1 - before, y0 - before, x1 + after, y1 + after, colour);
}

void draw_line(Image& image, Pixel a, Pixel b, Bgr colour, int thickness) {
  require_colour(image, "draw_line");
  require_thickness(thickness, "draw_line");
  if (!finite(a) || !finite(b)) return;
  const double half = thickness / 2.0;
  if (thickness > 1) {  // round ends
    fill_circle(image, a, half, colour);
    fill_circle(image, b, half, colour);
  }
  // Walk along the longer axis ("major", u), one pixel at a time, and paint
  // the pixels across it ("minor", v) that the line covers there. Written
  // once for x-major lines; a y-major line swaps the roles.
  const bool x_major = std::abs(b.x - a.x) >= std::abs(b.y - a.y);
  double ua = x_major ? a.x : a.y, va = x_major ? a.y : a.x;
  double ub = x_major ? b.x : b.y, vb = x_major ? b.y : b.x;
  if (ua > ub) {
    std::swap(ua, ub);
    std::swap(va, vb);
  }
  const int u_size = x_major ? image.width() : image.height();
  const double slope = ub > ua ? (vb - va) / (ub - ua) : 0.0;  // |slope| <= 1
  // Across the line, thickness / 2 is this much along the minor axis.
  const double reach = half * std::sqrt(1.0 + slope * slope);
  const double u0 = std::max(std::floor(ua + 0.5), 0.0);
  const double u1 = std::min(std::floor(ub + 0.5), u_size - 1.0);
  for (double u = u0; u <= u1; u += 1.0) {
    const double v = va + slope * (std::clamp(u, ua, ub) - ua);
    // One pixel (the nearest) for a thin line; else the pixel centres c
    // with v - reach <= c < v + reach.
    const double v0 = thickness == 1 ? std::floor(v + 0.5) : std::ceil(v - reach);
    const double v1 = thickness == 1 ? v0 : std::ceil(v + reach) - 1.0;
    const int ui = static_cast<int>(u);
    if (x_major)
      column_span(image, ui, v0, v1, colour);
    else
      span(image, ui, v0, v1, colour);
  }
}

void fill_circle(Image& image, Pixel centre, double radius, Bgr colour) {
  require_colour(image, "fill_circle");
  if (radius < 0.0) throw std::invalid_argument("fill_circle: radius must be >= 0");
  if (!finite(centre) || !std::isfinite(radius)) return;
  const double y0 =
      std::max(std::ceil(centre.y - radius), static_cast<double>(image.first_row()));
  const double y1 = std::min(std::floor(centre.y + radius), image.end_row() - 1.0);
  for (double y = y0; y <= y1; y += 1.0) {
    const double dy = y - centre.y;
    const double dx = std::sqrt(std::max(radius * radius - dy * dy, 0.0));
    span(image, static_cast<int>(y), std::ceil(centre.x - dx),
         std::floor(centre.x + dx), colour);
  }
}

void draw_ellipse(Image& image, Pixel centre, double semi_a, double semi_b,
                  double angle, Bgr colour, int thickness) {
  require_colour(image, "draw_ellipse");
  require_thickness(thickness, "draw_ellipse");
  if (semi_a < 0.0 || semi_b < 0.0)
    throw std::invalid_argument("draw_ellipse: semi-axes must be >= 0");
  if (!finite(centre) || !std::isfinite(semi_a) || !std::isfinite(semi_b) ||
      !std::isfinite(angle))
    return;
  // Segments about 2 pixels long: they stray from the curve by well under a
  // pixel. Capped for huge ellipses, which mostly lie off the image.
  const double longest = std::max(semi_a, semi_b);
  const int n = static_cast<int>(std::clamp(std::ceil(M_PI * longest), 12.0, 4096.0));
  const double ca = std::cos(angle), sa = std::sin(angle);
  const auto at = [&](int k) {
    const double t = 2.0 * M_PI * k / n;
    const double p = semi_a * std::cos(t), q = semi_b * std::sin(t);
    return Pixel{centre.x + p * ca - q * sa, centre.y + p * sa + q * ca};
  };
  Pixel prev = at(0);
  for (int k = 1; k <= n; ++k) {
    const Pixel next = at(k % n);
    draw_line(image, prev, next, colour, thickness);
    prev = next;
  }
}

void draw_circle(Image& image, Pixel centre, double radius, Bgr colour,
                 int thickness) {
  draw_ellipse(image, centre, radius, radius, 0.0, colour, thickness);
}

void draw_digits(Image& image, const std::string& text, int x, int y, int scale,
                 Bgr colour) {
  require_colour(image, "draw_digits");
  if (scale < 1) throw std::invalid_argument("draw_digits: scale must be >= 1");
  // In long long: a large scale or a far origin must not overflow.
  const long long s = scale;
  const long long top = y - kGlyphHeight * s + 1;
  for (size_t i = 0; i < text.size(); ++i) {
    const uint8_t* rows = glyph(text[i]);
    if (!rows) continue;
    const long long left = x + static_cast<long long>(i) * kGlyphAdvance * s;
    for (int gy = 0; gy < kGlyphHeight; ++gy) {
      const long long r0 = std::max(top + gy * s, static_cast<long long>(image.first_row()));
      const long long r1 = std::min(top + (gy + 1) * s, static_cast<long long>(image.end_row()));
      for (int gx = 0; gx < kGlyphWidth; ++gx)
        if (rows[gy] & (0x10 >> gx))
          for (long long r = r0; r < r1; ++r) {
            const double c0 = static_cast<double>(left + gx * s);
            span(image, static_cast<int>(r), c0, c0 + static_cast<double>(s - 1), colour);
          }
    }
  }
}

int digit_scale(double font_scale) {
  if (!(font_scale > 0.0)) return 1;
  return static_cast<int>(std::clamp(std::round(3.0 * font_scale), 1.0, 1000.0));
}

}  // namespace hmt::grid

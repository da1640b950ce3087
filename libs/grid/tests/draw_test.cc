#include "hmt/grid/draw.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <set>
#include <stdexcept>
#include <utility>

namespace hmt::grid {
namespace {

const Bgr kBack = Bgr::grey(205);
const Bgr kInk{10, 20, 30};

Image canvas(int w = 40, int h = 30) { return grey_to_bgr(Image(w, h, 1, 205)); }

// The painted pixels, as (x, y).
std::set<std::pair<int, int>> ink(const Image& img) {
  std::set<std::pair<int, int>> out;
  for (int y = 0; y < img.height(); ++y)
    for (int x = 0; x < img.width(); ++x)
      if (img.bgr(x, y) != kBack) out.insert({x, y});
  return out;
}

// Draws with `draw` (given an offset to add to every coordinate) on a small
// image and, shifted by a margin, on one large enough to hold the whole
// shape: the small image must be exactly the matching window of the large
// one, i.e. clipping changes nothing inside and writes nothing outside.
void expect_clipped(const std::function<void(Image&, int offset)>& draw) {
  constexpr int kW = 20, kH = 15, kMargin = 200;
  Image small = canvas(kW, kH);
  draw(small, 0);
  Image large = canvas(kW + 2 * kMargin, kH + 2 * kMargin);
  draw(large, kMargin);
  ASSERT_EQ(small.width(), kW);
  ASSERT_EQ(small.pixels().size(), size_t{kW * kH * 3});
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      ASSERT_EQ(small.bgr(x, y), large.bgr(x + kMargin, y + kMargin)) << x << ", " << y;
}

TEST(Draw, OnlyColourImages) {
  Image grey(5, 5, 1);
  EXPECT_THROW(fill_rect(grey, 0, 0, 1, 1, kInk), std::invalid_argument);
  EXPECT_THROW(draw_line(grey, {0, 0}, {3, 3}, kInk), std::invalid_argument);
  EXPECT_THROW(draw_digits(grey, "1", 0, 6, 1, kInk), std::invalid_argument);
  Image img = canvas();
  EXPECT_THROW(draw_line(img, {0, 0}, {3, 3}, kInk, 0), std::invalid_argument);
  EXPECT_THROW(fill_circle(img, {3, 3}, -1.0, kInk), std::invalid_argument);
  EXPECT_THROW(draw_ellipse(img, {3, 3}, 2, -1, 0, kInk), std::invalid_argument);
  EXPECT_THROW(draw_digits(img, "1", 0, 6, 0, kInk), std::invalid_argument);
  EXPECT_TRUE(ink(img).empty());
}

TEST(Draw, RectanglesFilledAndOutlined) {
  Image img = canvas();
  fill_rect(img, 5, 4, 2, 3, kInk);  // corners in any order
  EXPECT_EQ(ink(img).size(), 8u);
  EXPECT_EQ(img.bgr(2, 3), kInk);
  EXPECT_EQ(img.bgr(5, 4), kInk);

  img = canvas();
  draw_rect(img, 10, 10, 19, 14, kInk);
  EXPECT_EQ(ink(img).size(), 2u * 10 + 2u * 3);  // the border of 10 x 5
  EXPECT_EQ(img.bgr(10, 10), kInk);
  EXPECT_EQ(img.bgr(19, 14), kInk);
  EXPECT_EQ(img.bgr(15, 12), kBack);  // inside untouched
  img = canvas();
  draw_rect(img, 10, 10, 19, 14, kInk, 3);  // a band from 9 to 20, 9 to 15
  EXPECT_EQ(img.bgr(9, 9), kInk);
  EXPECT_EQ(img.bgr(20, 15), kInk);
  EXPECT_EQ(img.bgr(11, 11), kInk);
  EXPECT_EQ(img.bgr(12, 12), kBack);
  EXPECT_EQ(img.bgr(8, 8), kBack);
}

TEST(Draw, ThinLinesPaintOnePixelPerStep) {
  Image img = canvas();
  draw_line(img, {2, 5}, {12, 5}, kInk);
  EXPECT_EQ(ink(img).size(), 11u);
  for (int x = 2; x <= 12; ++x) EXPECT_EQ(img.bgr(x, 5), kInk) << x;

  // A shallow diagonal: one pixel per column, 8-connected, ends included.
  img = canvas();
  draw_line(img, {30, 20}, {3, 8}, kInk);
  const auto px = ink(img);
  EXPECT_EQ(px.size(), 28u);
  EXPECT_TRUE(px.count({3, 8}));
  EXPECT_TRUE(px.count({30, 20}));
  int last = -1;
  for (const auto& [x, y] : px) {
    if (last >= 0) {
      EXPECT_LE(std::abs(y - last), 1) << x;
    }
    last = y;
  }
  // Steep: one pixel per row.
  img = canvas();
  draw_line(img, {5, 2}, {8, 27}, kInk);
  EXPECT_EQ(ink(img).size(), 26u);
  // A point.
  img = canvas();
  draw_line(img, {4.2, 6.8}, {4.2, 6.8}, kInk);
  EXPECT_EQ(ink(img), (std::set<std::pair<int, int>>{{4, 7}}));
}

TEST(Draw, ThickLinesCoverTheirWidthWithRoundEnds) {
  Image img = canvas();
  draw_line(img, {5, 10}, {25, 10}, kInk, 3);
  for (int x = 5; x <= 25; ++x)
    for (int y = 9; y <= 11; ++y) EXPECT_EQ(img.bgr(x, y), kInk) << x << ", " << y;
  EXPECT_EQ(img.bgr(15, 8), kBack);
  EXPECT_EQ(img.bgr(15, 12), kBack);
  EXPECT_EQ(img.bgr(4, 10), kInk);   // the round end reaches 1.5 pixels out
  EXPECT_EQ(img.bgr(3, 10), kBack);
  EXPECT_EQ(img.bgr(4, 9), kInk);    // within 1.5 of the end...
  EXPECT_EQ(img.bgr(4, 8), kBack);   // ...but round, not square
  // Diagonal: the pixels on the line and next to it across.
  img = canvas();
  draw_line(img, {5, 5}, {20, 20}, kInk, 3);
  EXPECT_EQ(img.bgr(12, 12), kInk);
  EXPECT_EQ(img.bgr(13, 12), kInk);
  EXPECT_EQ(img.bgr(12, 13), kInk);
  EXPECT_EQ(img.bgr(14, 12), kInk);   // 1.41 from the line
  EXPECT_EQ(img.bgr(15, 12), kBack);  // 2.12
}

TEST(Draw, FilledCirclesHoldThePixelsWithinTheRadius) {
  Image img = canvas();
  fill_circle(img, {10, 10}, 3.0, kInk);
  int n = 0;
  for (int dy = -3; dy <= 3; ++dy)
    for (int dx = -3; dx <= 3; ++dx)
      if (dx * dx + dy * dy <= 9) {
        ++n;
        EXPECT_EQ(img.bgr(10 + dx, 10 + dy), kInk) << dx << ", " << dy;
      }
  EXPECT_EQ(ink(img).size(), static_cast<size_t>(n));
  img = canvas();
  fill_circle(img, {10.5, 10.5}, 0.5, kInk);  // between four pixels
  EXPECT_TRUE(ink(img).empty());
  fill_circle(img, {10.5, 10.5}, 0.75, kInk);
  EXPECT_EQ(ink(img).size(), 4u);
}

TEST(Draw, EllipsesReachTheirSemiAxesAlongTheirAngle) {
  const auto extent = [](const Image& img, int cx, int cy) {
    int ex = 0, ey = 0;
    for (const auto& [x, y] : ink(img)) {
      ex = std::max(ex, std::abs(x - cx));
      ey = std::max(ey, std::abs(y - cy));
    }
    return std::make_pair(ex, ey);
  };
  Image img = canvas(60, 60);
  draw_ellipse(img, {30, 30}, 20, 8, 0.0, kInk);
  EXPECT_EQ(extent(img, 30, 30), std::make_pair(20, 8));
  EXPECT_EQ(img.bgr(50, 30), kInk);
  EXPECT_EQ(img.bgr(30, 22), kInk);
  EXPECT_EQ(img.bgr(30, 30), kBack);  // an outline
  EXPECT_EQ(img.bgr(40, 30), kBack);
  // A closed curve: every column from 10 to 50 has a pixel above and below.
  for (int x = 10; x <= 50; ++x) {
    bool above = false, below = false;
    for (int y = 0; y < 60; ++y)
      if (img.bgr(x, y) == kInk) (y <= 30 ? above : below) = true;
    EXPECT_TRUE(above && below) << x;
  }
  img = canvas(60, 60);
  draw_ellipse(img, {30, 30}, 20, 8, M_PI / 2, kInk);  // turned to the rows
  EXPECT_EQ(extent(img, 30, 30), std::make_pair(8, 20));
  img = canvas(60, 60);
  draw_circle(img, {30, 30}, 10, kInk, 2);
  EXPECT_EQ(extent(img, 30, 30), std::make_pair(11, 11));
  EXPECT_EQ(img.bgr(30, 30), kBack);
}

TEST(Draw, DigitsRenderInTheirFont) {
  Image img = canvas(70, 20);
  draw_digits(img, "0123456789", 1, 8, 1, kInk);
  const auto px = ink(img);
  ASSERT_FALSE(px.empty());
  int x0 = 99, x1 = -1, y0 = 99, y1 = -1;
  for (const auto& [x, y] : px)
    x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  EXPECT_EQ(y0, 2);  // 7 rows ending at the given bottom row
  EXPECT_EQ(y1, 8);
  EXPECT_EQ(x0, 1);
  EXPECT_EQ(x1, 1 + 9 * kGlyphAdvance + kGlyphWidth - 1);
  // Every digit is drawn, and no two alike.
  std::set<std::set<std::pair<int, int>>> glyphs;
  for (int d = 0; d < 10; ++d) {
    std::set<std::pair<int, int>> g;
    for (const auto& [x, y] : px)
      if (x >= 1 + d * kGlyphAdvance && x < 1 + (d + 1) * kGlyphAdvance)
        g.insert({x - d * kGlyphAdvance, y});
    EXPECT_FALSE(g.empty()) << d;
    glyphs.insert(g);
  }
  EXPECT_EQ(glyphs.size(), 10u);
  // Scaled: every font pixel a square, the text as many times larger.
  Image one = canvas(70, 40), three = canvas(70, 40);
  draw_digits(one, "42", 0, 6, 1, kInk);
  draw_digits(three, "42", 0, 20, 3, kInk);
  EXPECT_EQ(ink(three).size(), 9 * ink(one).size());
  for (const auto& [x, y] : ink(one))
    EXPECT_EQ(three.bgr(3 * x + 2, 3 * y + 2), kInk);
  // Anything but digits and '-' is blank, but takes its place.
  Image a = canvas(), b = canvas();
  draw_digits(a, "7x7", 0, 10, 1, kInk);
  draw_digits(b, "7", 0, 10, 1, kInk);
  draw_digits(b, "7", 2 * kGlyphAdvance, 10, 1, kInk);
  EXPECT_EQ(a.pixels(), b.pixels());
  EXPECT_EQ(digit_scale(0.4), 1);
  EXPECT_EQ(digit_scale(1.0), 3);
  EXPECT_EQ(digit_scale(0.0), 1);
}

TEST(Draw, ShapesPartlyOutsideAreClipped) {
  const auto at = [](double v, int offset) { return v + offset; };
  expect_clipped([&](Image& img, int o) {
    draw_line(img, {at(-30, o), at(-7, o)}, {at(45, o), at(22, o)}, kInk);
  });
  expect_clipped([&](Image& img, int o) {
    draw_line(img, {at(-3.3, o), at(40, o)}, {at(12.6, o), at(-25, o)}, kInk, 4);
  });
  expect_clipped([&](Image& img, int o) {
    fill_circle(img, {at(18.5, o), at(-2, o)}, 6.3, kInk);
  });
  expect_clipped([&](Image& img, int o) {
    draw_ellipse(img, {at(3, o), at(12, o)}, 25, 9, 0.4, kInk, 3);
  });
  expect_clipped([&](Image& img, int o) {
    draw_rect(img, -5 + o, 3 + o, 30 + o, 40 + o, kInk, 3);
  });
  expect_clipped([&](Image& img, int o) {
    fill_rect(img, -50 + o, -50 + o, 5 + o, 50 + o, kInk);
  });
  expect_clipped([&](Image& img, int o) {
    draw_digits(img, "90817", -8 + o, 3 + o, 2, kInk);
  });
}

// Draws with `draw` on a whole image and on every band of it (bands of
// `band_rows` rows): each band must hold exactly the whole image's rows.
void expect_banded(const std::function<void(Image&)>& draw, int band_rows) {
  constexpr int kW = 40, kH = 30;
  Image whole = canvas(kW, kH);
  draw(whole);
  for (int first = 0; first < kH; first += band_rows) {
    const int rows = std::min(band_rows, kH - first);
    Image band = grey_to_bgr(Image::band(kW, kH, first, rows, 1, 205));
    ASSERT_EQ(band.first_row(), first);
    ASSERT_EQ(band.end_row(), first + rows);
    ASSERT_EQ(band.pixels().size(), static_cast<size_t>(kW * rows * 3));
    draw(band);
    for (int y = first; y < first + rows; ++y)
      for (int x = 0; x < kW; ++x)
        ASSERT_EQ(band.bgr(x, y), whole.bgr(x, y)) << x << ", " << y << " band " << first;
  }
}

TEST(Draw, DrawingBandByBandPaintsTheWholeImage) {
  for (int band_rows : {1, 4, 7, 30}) {
    SCOPED_TRACE(band_rows);
    expect_banded([](Image& img) {
      draw_line(img, {-30, -7}, {45, 22}, kInk);
      draw_line(img, {-3.3, 40}, {12.6, -25}, kInk, 4);
      fill_circle(img, {18.5, 12.2}, 6.3, kInk);
      draw_ellipse(img, {20.3, 14.8}, 25, 9, 0.4, kInk, 3);
      draw_circle(img, {7.5, 21.5}, 5, kInk);
      draw_rect(img, -5, 3, 30, 40, kInk, 3);
      fill_rect(img, 33, 2, 36, 27, kInk);
      draw_digits(img, "90817", 2, 20, 2, kInk);
    }, band_rows);
  }
}

TEST(Draw, BandsOutsideTheImageAreRejected) {
  EXPECT_THROW(Image::band(10, 10, -1, 3, 1), std::invalid_argument);
  EXPECT_THROW(Image::band(10, 10, 8, 3, 1), std::invalid_argument);
  EXPECT_THROW(Image::band(10, 10, 2, -1, 1), std::invalid_argument);
  const Image b = Image::band(10, 10, 7, 3, 1);
  EXPECT_EQ(b.height(), 10);
  EXPECT_FALSE(b.contains(0, 6));
  EXPECT_TRUE(b.contains(0, 7));
  EXPECT_TRUE(b.contains(9, 9));
  EXPECT_FALSE(b.contains(0, 10));
}

TEST(Draw, FarAwayAndNonFiniteShapesDrawNothing) {
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Image img = canvas();
  draw_line(img, {-1e300, 5}, {-1e299, 1e300}, kInk, 3);
  draw_line(img, {1e9, 1e9}, {2e9, 3e9}, kInk);
  draw_line(img, {0, 0}, {inf, 5}, kInk);
  draw_line(img, {nan, 0}, {5, 5}, kInk);
  fill_circle(img, {1e12, 5}, 100.0, kInk);
  fill_circle(img, {5, 5}, inf, kInk);
  draw_ellipse(img, {5, 5}, nan, 2, 0, kInk);
  draw_ellipse(img, {-1e7, 5}, 1e6, 1e6, 0.3, kInk);
  fill_rect(img, 1000000, 5, 2000000, 9, kInk);
  draw_digits(img, "123", 2000000000, 5, 1000, kInk);
  draw_digits(img, "123", -2000000000, -2000000000, 1000, kInk);
  EXPECT_TRUE(ink(img).empty());
  // A huge ellipse around the image crosses it: only its part inside.
  draw_ellipse(img, {20, 1e4}, 1e4, 1e4 - 10, 0.0, kInk);
  EXPECT_FALSE(ink(img).empty());
}

}  // namespace
}  // namespace hmt::grid

// The 8-bit images the project draws and writes: grey maps and the colour
// pictures drawn over them. Our own small type rather than cv::Mat: loading
// OpenCV's libraries costs every run several megabytes of resident memory,
// and these images need no more than a pixel buffer.
#pragma once

#include <cstdint>
#include <ostream>
#include <vector>

namespace hmt::grid {

// A colour in the order the pixels hold it: blue, green, red, as OpenCV
// does, so that its decoder reads our PNGs back into the same bytes
// (hmt/grid/png.h stores them as RGB, the file format's order).
struct Bgr {
  uint8_t b = 0;
  uint8_t g = 0;
  uint8_t r = 0;
  static constexpr Bgr grey(uint8_t v) { return {v, v, v}; }
  friend bool operator==(const Bgr& x, const Bgr& y) {
    return x.b == y.b && x.g == y.g && x.r == y.r;
  }
  friend bool operator!=(const Bgr& x, const Bgr& y) { return !(x == y); }
  friend std::ostream& operator<<(std::ostream& os, const Bgr& c) {
    return os << "Bgr(" << int(c.b) << ", " << int(c.g) << ", " << int(c.r) << ")";
  }
};

// width x height pixels of 1 (grey) or 3 (B, G, R) channels, rows top to
// bottom, each row's pixels left to right with their channels interleaved,
// no padding. Pixels are addressed (x, y) = (column, row).
//
// A band: the rows [first_row, first_row + rows) of a width x height image,
// the only ones it holds. Pixels keep the whole image's coordinates, and
// drawing on a band (hmt/grid/draw.h) paints exactly the pixels that drawing
// on the whole image would paint in those rows. So a large map is drawn and
// written band by band (hmt/grid/row_source.h) without ever being held whole.
class Image {
 public:
  Image() = default;  // empty: 0 x 0
  // Throws std::invalid_argument for a negative size or channels not 1 or 3.
  Image(int width, int height, int channels, uint8_t fill = 0);
  // The band of `rows` rows from `first_row` of a width x height image;
  // throws std::invalid_argument unless 0 <= first_row <= first_row + rows
  // <= height.
  static Image band(int width, int height, int first_row, int rows, int channels,
                    uint8_t fill = 0);

  int width() const { return width_; }
  int height() const { return height_; }
  int channels() const { return channels_; }
  // The rows held: [first_row(), end_row()); all of them but for a band.
  int first_row() const { return first_row_; }
  int end_row() const { return first_row_ + rows_; }
  bool empty() const { return width_ == 0 || height_ == 0; }
  bool contains(int x, int y) const {
    return x >= 0 && y >= first_row_ && x < width_ && y < end_row();
  }

  // Unchecked access (x, y held: contains(x, y); c < channels()).
  uint8_t* row(int y) { return pixels_.data() + offset(0, y); }
  const uint8_t* row(int y) const { return pixels_.data() + offset(0, y); }
  uint8_t& at(int x, int y, int c = 0) { return pixels_[offset(x, y) + c]; }
  uint8_t at(int x, int y, int c = 0) const { return pixels_[offset(x, y) + c]; }
  // A colour image's pixel.
  Bgr bgr(int x, int y) const {
    const uint8_t* p = pixels_.data() + offset(x, y);
    return {p[0], p[1], p[2]};
  }

  const std::vector<uint8_t>& pixels() const { return pixels_; }

 private:
  size_t offset(int x, int y) const {
    return (static_cast<size_t>(y - first_row_) * static_cast<size_t>(width_) +
            static_cast<size_t>(x)) * static_cast<size_t>(channels_);
  }

  int width_ = 0;
  int height_ = 0;
  int channels_ = 1;
  int first_row_ = 0;
  int rows_ = 0;
  std::vector<uint8_t> pixels_;
};

// A 3-channel copy of a grey image (its level in B, G and R), to draw on in
// colour (a band of a band). Throws std::invalid_argument if `grey` has not 1
// channel.
Image grey_to_bgr(const Image& grey);

}  // namespace hmt::grid

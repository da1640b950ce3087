// An image produced row by row, top to bottom, for the writers (PNG, PGM)
// to consume in order. A global map at 5 cm over a 2 km run is tens of
// millions of pixels, three times that in colour: rendered and drawn band by
// band (hmt/grid/image.h), the whole picture never sits in memory, and a
// run's peak memory no longer grows with the extent of its map.
#pragma once

#include <cstdint>

#include "hmt/grid/image.h"

namespace hmt::grid {

class RowSource {
 public:
  virtual ~RowSource() = default;
  virtual int width() const = 0;
  virtual int height() const = 0;
  virtual int channels() const = 0;  // 1 (grey) or 3 (B, G, R)
  // Row y (0 = the top): width() * channels() bytes, valid until the next
  // call. Called with y = 0, 1, ..., height() - 1, in that order.
  virtual const uint8_t* row(int y) = 0;
};

// The rows of an image held whole.
class ImageRows : public RowSource {
 public:
  explicit ImageRows(const Image& image) : image_(image) {}
  int width() const override { return image_.width(); }
  int height() const override { return image_.height(); }
  int channels() const override { return image_.channels(); }
  const uint8_t* row(int y) override { return image_.row(y); }

 private:
  const Image& image_;
};

// The rows of an image made band by band: make_band(first_row, rows) is
// called for each band of band_rows rows (the last may be shorter), in
// order, as row() reaches it.
class BandRows : public RowSource {
 public:
  BandRows(int width, int height, int channels, int band_rows)
      : width_(width), height_(height), channels_(channels), band_rows_(band_rows) {}
  int width() const override { return width_; }
  int height() const override { return height_; }
  int channels() const override { return channels_; }
  const uint8_t* row(int y) override {
    if (band_.empty() || y < band_.first_row() || y >= band_.end_row()) {
      const int first = y - y % band_rows_;
      const int rows = first + band_rows_ <= height_ ? band_rows_ : height_ - first;
      band_ = Image();  // release the previous band before making the next
      band_ = make_band(first, rows);
    }
    return band_.row(y);
  }

 protected:
  // A band of this source's size: Image::band(width(), height(), first_row,
  // rows, channels()).
  virtual Image make_band(int first_row, int rows) = 0;

 private:
  int width_, height_, channels_, band_rows_;
  Image band_;
};

}  // namespace hmt::grid

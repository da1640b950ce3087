#include "hmt/grid/image.h"

#include <stdexcept>
#include <string>

namespace hmt::grid {

Image::Image(int width, int height, int channels, uint8_t fill)
    : width_(width), height_(height), channels_(channels), rows_(height) {
  if (width < 0 || height < 0)
    throw std::invalid_argument("Image: negative size " + std::to_string(width) +
                                " x " + std::to_string(height));
  if (channels != 1 && channels != 3)
    throw std::invalid_argument("Image: " + std::to_string(channels) +
                                " channels (1 or 3 supported)");
  pixels_.assign(static_cast<size_t>(width) * static_cast<size_t>(height) *
                     static_cast<size_t>(channels),
                 fill);
}

Image Image::band(int width, int height, int first_row, int rows, int channels,
                   uint8_t fill) {
  if (first_row < 0 || rows < 0 || rows > height - first_row)
    throw std::invalid_argument("Image::band: rows " + std::to_string(first_row) + " to " +
                                std::to_string(first_row + rows) +
                                " outside an image of height " + std::to_string(height));
  Image out(width, rows, channels, fill);
  out.height_ = height;
  out.first_row_ = first_row;
  return out;
}

Image grey_to_bgr(const Image& grey) {
  if (grey.channels() != 1)
    throw std::invalid_argument("grey_to_bgr: the image is not grey");
  Image out = Image::band(grey.width(), grey.height(), grey.first_row(),
                          grey.end_row() - grey.first_row(), 3);
  for (int y = grey.first_row(); y < grey.end_row(); ++y) {
    const uint8_t* in = grey.row(y);
    uint8_t* o = out.row(y);
    for (int x = 0; x < grey.width(); ++x, o += 3) o[0] = o[1] = o[2] = in[x];
  }
  return out;
}

}  // namespace hmt::grid

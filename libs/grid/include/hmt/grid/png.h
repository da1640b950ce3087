// PNG files of the images the project draws (grey maps, colour overlays),
// encoded with libpng rather than OpenCV's imgcodecs: imgcodecs loads some
// hundred shared libraries (GDAL, poppler, HDF5, ...) into every process
// that links it, which dominated the resident memory of the tools. The
// encoder uses cv::imencode's settings (SUB filter, deflate level 1,
// run-length strategy), so with the same libpng and zlib the files are
// byte for byte those imencode wrote.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hmt/grid/image.h"
#include "hmt/grid/row_source.h"

namespace hmt::grid {

// The PNG bytes of a grey or BGR image; colour is stored as RGB, as
// cv::imencode does, so that any reader gets the same pixels back. Throws
// hmt::OutputError, naming `path` (the file the bytes are for), for an empty
// image or an encoder failure.
std::vector<uint8_t> encode_png(const Image& image, const std::string& path);

// encode_png() written atomically to `path` (complete or absent, see
// hmt/common/files.h). Throws hmt::OutputError on failure.
void write_png_file(const Image& image, const std::string& path);
// The same, encoding the rows as the source makes them, straight into the
// file: neither the image nor its PNG bytes are ever held whole. Throws
// hmt::OutputError (the source's own failure included); the file is then
// left as it was.
void write_png_file(RowSource& rows, const std::string& path);

}  // namespace hmt::grid

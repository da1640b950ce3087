#include "hmt/grid/png.h"

#include <png.h>
#include <zlib.h>

#include <cstdio>
#include <new>
#include <ostream>

#include "hmt/common/error.h"
#include "hmt/common/files.h"

namespace hmt::grid {
namespace {

// What libpng's callbacks reach: where the output goes (a growing buffer,
// or a stream when `bytes` is null) and the error message.
struct Sink {
  std::vector<uint8_t>* bytes;
  std::ostream* stream;
  char message[256];
};

// libpng reports an error by calling this, which must not return: it jumps
// back to the setjmp in encode().
void on_error(png_structp png, png_const_charp message) {
  Sink* sink = static_cast<Sink*>(png_get_error_ptr(png));
  std::snprintf(sink->message, sizeof sink->message, "%s", message);
  png_longjmp(png, 1);
}

void on_warning(png_structp, png_const_charp) {}  // nothing the user can act on

void on_write(png_structp png, png_bytep data, size_t size) {
  Sink* sink = static_cast<Sink*>(png_get_io_ptr(png));
  bool stored = true;
  try {
    if (sink->bytes) {
      sink->bytes->insert(sink->bytes->end(), data, data + size);
    } else {
      sink->stream->write(reinterpret_cast<const char*>(data),
                          static_cast<std::streamsize>(size));
      stored = static_cast<bool>(*sink->stream);
    }
  } catch (const std::exception&) {
    stored = false;
  }
  // Outside the handler: png_error jumps, and no exception may be pending.
  if (!stored) png_error(png, sink->bytes ? "out of memory" : "write failed");
}

void on_flush(png_structp) {}

// One row from the source, or null with the reason in the sink (an
// exception must not cross the libpng frames).
const uint8_t* fetch_row(RowSource& rows, int y, Sink* sink) {
  try {
    return rows.row(y);
  } catch (const std::exception& e) {
    std::snprintf(sink->message, sizeof sink->message, "%s", e.what());
  }
  return nullptr;
}

// The libpng calls. An error jumps from inside them back to the setjmp
// here, over this frame and libpng's: every local is trivially
// destructible, so that the jump skips no destructor.
bool encode(RowSource& image, int colour_type, Sink* sink) {
  png_structp png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, sink, on_error, on_warning);
  if (!png) {
    std::snprintf(sink->message, sizeof sink->message, "cannot create the encoder");
    return false;
  }
  png_infop info = png_create_info_struct(png);
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    std::snprintf(sink->message, sizeof sink->message, "cannot create the encoder");
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, sink, on_write, on_flush);
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.width()),
               static_cast<png_uint_32>(image.height()), 8, colour_type,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  // cv::imencode's settings: fast, and maps are mostly long runs of one
  // grey, which run-length deflate packs well (libpng's defaults take
  // 5-7 times as long for files 30% smaller).
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
  png_set_compression_level(png, Z_BEST_SPEED);
  png_set_compression_strategy(png, Z_RLE);
  png_write_info(png, info);
  if (image.channels() == 3) png_set_bgr(png);  // the order in memory
  for (int r = 0; r < image.height(); ++r) {
    const uint8_t* row = fetch_row(image, r, sink);
    if (!row) {
      png_destroy_write_struct(&png, &info);
      return false;
    }
    // libpng does not write through the row pointer (png_write_row takes
    // png_const_bytep since 1.5).
    png_write_row(png, row);
  }
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return true;
}

int colour_type(const RowSource& image, const std::string& path) {
  if (image.width() == 0 || image.height() == 0)
    throw OutputError("cannot write an empty image to '" + path + "'");
  return image.channels() == 3 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_GRAY;
}

}  // namespace

std::vector<uint8_t> encode_png(const Image& image, const std::string& path) {
  ImageRows rows(image);
  const int type = colour_type(rows, path);
  std::vector<uint8_t> bytes;
  Sink sink{&bytes, nullptr, {}};
  if (!encode(rows, type, &sink))
    throw OutputError("cannot encode PNG for '" + path + "': " + sink.message);
  return bytes;
}

void write_png_file(RowSource& rows, const std::string& path) {
  const int type = colour_type(rows, path);
  write_file_atomically(path, [&](std::ostream& os) {
    Sink sink{nullptr, &os, {}};
    if (!encode(rows, type, &sink))
      throw OutputError("cannot encode PNG for '" + path + "': " + sink.message);
  });
}

void write_png_file(const Image& image, const std::string& path) {
  ImageRows rows(image);
  write_png_file(rows, path);
}

}  // namespace hmt::grid

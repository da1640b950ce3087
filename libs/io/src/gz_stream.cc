#include "gz_stream.h"

#include <algorithm>
#include <climits>
#include <stdexcept>

#include "hmt/common/error.h"

namespace hmt::io::detail {

GzInputStream::GzInputStream(const std::string& path) : path_(path) {
  file_ = gzopen(path.c_str(), "rb");
  if (!file_) throw InputError("cannot open input log '" + path + "'");
  gzbuffer(file_, 1 << 17);
}

GzInputStream::~GzInputStream() {
  if (file_) gzclose(file_);
}

uint64_t GzInputStream::file_offset() const {
  const z_off_t offset = gzoffset(file_);
  return offset > 0 ? static_cast<uint64_t>(offset) : 0;
}

size_t GzInputStream::read(void* buffer, size_t count) {
  auto* out = static_cast<char*>(buffer);
  size_t done = 0;
  while (done < count) {
    const size_t chunk = std::min<size_t>(count - done, INT_MAX / 2);
    const int got = gzread(file_, out + done, static_cast<unsigned>(chunk));
    if (got <= 0) break;
    done += static_cast<size_t>(got);
  }
  position_ += done;
  return done;
}

bool GzInputStream::at_end() {
  const int c = gzgetc(file_);
  if (c < 0) return true;
  gzungetc(c, file_);
  return false;
}

std::string GzInputStream::compression_error() const {
  // zlib also says "unexpected end of file" for a plain file read past its
  // end; that case is the caller's to describe.
  if (gzdirect(file_)) return {};
  int errnum = Z_OK;
  const char* msg = gzerror(file_, &errnum);
  if (errnum == Z_OK || errnum == Z_STREAM_END) return {};
  std::string text = msg ? msg : "zlib error " + std::to_string(errnum);
  // zlib prefixes the file name, which the caller's message already has.
  const std::string named = path_ + ": ";
  if (text.compare(0, named.size(), named) == 0) text.erase(0, named.size());
  return text;
}

GzOutputStream::GzOutputStream(std::ostream& out, bool gzip)
    : out_(out), gzip_(gzip) {
  if (gzip_) {
    // windowBits 15 + 16: a gzip header and trailer instead of raw zlib, so
    // that gunzip and MRPT's own CFileGZInputStream read the result.
    if (deflateInit2(&zs_, Z_DEFAULT_COMPRESSION, Z_DEFLATED, 15 + 16, 8,
                     Z_DEFAULT_STRATEGY) != Z_OK)
      throw std::runtime_error("cannot initialise the gzip compressor");
  }
}

GzOutputStream::~GzOutputStream() {
  if (gzip_) deflateEnd(&zs_);
}

bool GzOutputStream::write(const void* buffer, size_t count) {
  if (!ok_ || finished_) return false;
  if (!gzip_) {
    out_.write(static_cast<const char*>(buffer),
               static_cast<std::streamsize>(count));
    ok_ = static_cast<bool>(out_);
  } else {
    const auto* in = static_cast<const Bytef*>(buffer);
    size_t done = 0;
    while (ok_ && done < count) {
      const size_t chunk = std::min<size_t>(count - done, UINT_MAX / 2);
      zs_.next_in = const_cast<Bytef*>(in + done);
      zs_.avail_in = static_cast<uInt>(chunk);
      ok_ = deflate_chunk(Z_NO_FLUSH);
      done += chunk;
    }
  }
  if (ok_) position_ += count;
  return ok_;
}

bool GzOutputStream::deflate_chunk(int flush) {
  unsigned char buf[1 << 15];
  int ret;
  do {
    zs_.next_out = buf;
    zs_.avail_out = sizeof(buf);
    ret = deflate(&zs_, flush);
    if (ret == Z_STREAM_ERROR) return false;
    const size_t have = sizeof(buf) - zs_.avail_out;
    out_.write(reinterpret_cast<const char*>(buf),
               static_cast<std::streamsize>(have));
    if (!out_) return false;
  } while (zs_.avail_out == 0 || (flush == Z_FINISH && ret != Z_STREAM_END));
  return true;
}

bool GzOutputStream::finish() {
  if (!finished_ && ok_ && gzip_) {
    zs_.next_in = nullptr;
    zs_.avail_in = 0;
    ok_ = deflate_chunk(Z_FINISH);
  }
  finished_ = true;
  out_.flush();
  return ok_ && static_cast<bool>(out_);
}

}  // namespace hmt::io::detail

// zlib streams for the rawlog reader and writer.
//
// Reading goes through gzopen()/gzread(), which reads gzip and plain files
// alike, so one code path serves ".rawlog" and ".rawlog.gz". The stream
// counts the bytes it has handed out and says whether any are left, which is
// what lets the reader tell a clean end of file (nothing read for the next
// object) from a file cut in the middle of an object, and it keeps zlib's own
// diagnosis ("unexpected end of file", "incorrect data check") for messages.
#pragma once

#include <zlib.h>

#include <cstdint>
#include <ostream>
#include <string>

namespace hmt::io::detail {

class GzInputStream {
 public:
  // Throws hmt::InputError naming `path` if it cannot be opened.
  explicit GzInputStream(const std::string& path);
  ~GzInputStream();
  GzInputStream(const GzInputStream&) = delete;
  GzInputStream& operator=(const GzInputStream&) = delete;

  // Reads up to `count` bytes; returns how many were read (fewer only at the
  // end of the data or at damaged compressed data).
  size_t read(void* buffer, size_t count);
  uint64_t position() const { return position_; }
  const std::string& path() const { return path_; }
  // How far into the file (compressed bytes, if it is) reading has got.
  uint64_t file_offset() const;

  // True when no byte is left (peeks one byte and pushes it back).
  bool at_end();
  // zlib's complaint about the compressed data ("" when none): a truncated
  // or corrupted gzip file is only detected when reading reaches the damage.
  std::string compression_error() const;

 private:
  std::string path_;
  gzFile file_ = nullptr;
  uint64_t position_ = 0;
};

// Writes to a std::ostream, gzip-compressed or as is.
class GzOutputStream {
 public:
  GzOutputStream(std::ostream& out, bool gzip);
  ~GzOutputStream();
  GzOutputStream(const GzOutputStream&) = delete;
  GzOutputStream& operator=(const GzOutputStream&) = delete;

  // False once the underlying stream has failed (and from then on).
  bool write(const void* buffer, size_t count);
  uint64_t position() const { return position_; }

  // Flushes the compressor and writes the gzip trailer. Returns false if the
  // underlying stream failed at any point.
  bool finish();

 private:
  bool deflate_chunk(int flush);

  std::ostream& out_;
  bool gzip_;
  bool ok_ = true;
  bool finished_ = false;
  z_stream zs_{};
  uint64_t position_ = 0;
};

}  // namespace hmt::io::detail

// MRPT streams over zlib, for the rawlog reader and writer.
//
// Reading goes through gzopen()/gzread(), which reads gzip and plain files
// alike, so one code path serves ".rawlog" and ".rawlog.gz". The stream
// counts the bytes it has handed out, which is what lets the reader tell a
// clean end of file (nothing read for the next object) from a file cut in the
// middle of an object (MRPT reports both as "EOF"), and it keeps zlib's own
// diagnosis ("unexpected end of file", "incorrect data check") for messages.
#pragma once

#include <zlib.h>

#include <cstdint>
#include <ostream>
#include <string>

#include <mrpt/io/CStream.h>

namespace hmt::io::detail {

class GzInputStream : public mrpt::io::CStream {
 public:
  // Throws hmt::InputError naming `path` if it cannot be opened.
  explicit GzInputStream(const std::string& path);
  ~GzInputStream() override;
  GzInputStream(const GzInputStream&) = delete;
  GzInputStream& operator=(const GzInputStream&) = delete;

  // All `count` bytes, or 0: MRPT's readers of plain values ignore short
  // reads, so a partial read must look like a failure to them.
  size_t Read(void* buffer, size_t count) override;
  size_t Write(const void* buffer, size_t count) override;
  uint64_t Seek(int64_t offset, TSeekOrigin origin) override;
  uint64_t getTotalBytesCount() const override;
  uint64_t getPosition() const override { return position_; }
  std::string getStreamDescription() const override;

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
class OstreamOutputStream : public mrpt::io::CStream {
 public:
  OstreamOutputStream(std::ostream& out, bool gzip);
  ~OstreamOutputStream() override;
  OstreamOutputStream(const OstreamOutputStream&) = delete;
  OstreamOutputStream& operator=(const OstreamOutputStream&) = delete;

  size_t Read(void* buffer, size_t count) override;
  size_t Write(const void* buffer, size_t count) override;
  uint64_t Seek(int64_t offset, TSeekOrigin origin) override;
  uint64_t getTotalBytesCount() const override { return position_; }
  uint64_t getPosition() const override { return position_; }

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

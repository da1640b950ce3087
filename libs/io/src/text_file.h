// Reading the text formats (CARMEN, TUM), gzip or plain: whole, or line by
// line for logs too long to hold.
#pragma once

#include <zlib.h>

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace hmt::io::detail {

// A zlib file handle that closes itself.
struct GzCloser {
  void operator()(gzFile_s* f) const { gzclose(f); }
};
using GzHandle = std::unique_ptr<gzFile_s, GzCloser>;

// The decompressed content of `path` (plain files are read as they are).
// `what` names the file in messages ("CARMEN log", "TUM file"). Throws
// hmt::InputError if the file is missing, not a regular file, or a damaged
// gzip stream.
std::string read_text_file(const std::string& path, const std::string& what);

// The lines of `path` one at a time (decompressed; plain files as they are),
// holding one buffer of the file, not the file. A last line without a
// newline is a line. Throws hmt::InputError as read_text_file() does, for a
// damaged gzip stream when reading reaches the damage, and for a line longer
// than `max_line` bytes (a file without newlines is not a text log, and
// would otherwise be held whole).
class LineReader {
 public:
  static constexpr size_t kDefaultMaxLine = size_t{64} << 20;
  LineReader(const std::string& path, const std::string& what,
             size_t max_line = kDefaultMaxLine);

  // The next line, without its newline, into *line (valid until the next
  // call); false at the end of the file.
  bool next(std::string_view* line);

  // How far into the file (compressed bytes, if it is) reading has got.
  uint64_t file_offset() const;

 private:
  // Appends the next chunk of the file to buf_; false at its end.
  bool fill();

  std::string path_;
  std::string what_;
  size_t max_line_;
  size_t line_no_ = 0;
  GzHandle file_;
  std::string buf_;
  size_t start_ = 0;  // first byte of buf_ not yet handed out
  bool eof_ = false;
};

// Up to `max_bytes` of the decompressed start of `path`, for sniffing the
// format; never throws on damaged data (the real reader will say what is
// wrong), only on a file that cannot be opened.
std::string read_file_head(const std::string& path, size_t max_bytes);

// Splits a line on blanks (space, tab, CR, and other ASCII whitespace).
void split_fields(std::string_view line, std::vector<std::string_view>& out);

// Strict, locale-independent number parsing of a whole field; false if the
// field is not entirely a number. Accepts "nan"/"inf": callers that must
// reject them check std::isfinite themselves, to say which it was.
bool parse_double(std::string_view field, double& value);
bool parse_int(std::string_view field, long& value);

}  // namespace hmt::io::detail

#include "text_file.h"

#include <zlib.h>

#include <algorithm>
#include <charconv>
#include <memory>

#include "hmt/common/error.h"
#include "hmt/common/files.h"

namespace hmt::io::detail {
namespace {

GzHandle open_gz(const std::string& path, const std::string& what) {
  GzHandle f(gzopen(path.c_str(), "rb"));
  if (!f) throw InputError("cannot open " + what + " '" + path + "'");
  gzbuffer(f.get(), 1 << 17);
  return f;
}

// Appends up to `count` bytes of `f` to `out`; false at the end of the data.
// Throws for damaged gzip data.
bool append_chunk(gzFile f, const std::string& path, const std::string& what, size_t count,
                  std::string& out) {
  const size_t had = out.size();
  out.resize(had + count);
  const int got = gzread(f, out.data() + had, static_cast<unsigned>(count));
  out.resize(had + static_cast<size_t>(std::max(got, 0)));
  if (got > 0) return true;
  int errnum = Z_OK;
  const char* msg = gzerror(f, &errnum);
  if (got < 0 || (errnum != Z_OK && errnum != Z_STREAM_END)) {
    std::string text = msg ? msg : "error";
    // zlib prefixes the file name, which the message already has.
    if (text.compare(0, path.size() + 2, path + ": ") == 0) text.erase(0, path.size() + 2);
    throw InputError(what + " '" + path + "' is a damaged gzip file (zlib: " + text + ")");
  }
  return false;
}

constexpr size_t kChunk = 1 << 16;

}  // namespace

std::string read_text_file(const std::string& path, const std::string& what) {
  require_readable_file(path, what);
  GzHandle f = open_gz(path, what);
  std::string text;
  while (append_chunk(f.get(), path, what, kChunk, text)) {
  }
  return text;
}

LineReader::LineReader(const std::string& path, const std::string& what, size_t max_line)
    : path_(path), what_(what), max_line_(max_line) {
  require_readable_file(path, what);
  file_ = open_gz(path, what);
}

bool LineReader::fill() {
  if (eof_) return false;
  // Drop what was handed out before growing the buffer.
  buf_.erase(0, start_);
  start_ = 0;
  eof_ = !append_chunk(file_.get(), path_, what_, kChunk, buf_);
  return !eof_;
}

bool LineReader::next(std::string_view* line) {
  size_t scanned = start_;
  for (;;) {
    const size_t nl = buf_.find('\n', scanned);
    if (nl != std::string::npos && nl - start_ <= max_line_) {
      ++line_no_;
      *line = std::string_view(buf_).substr(start_, nl - start_);
      start_ = nl + 1;
      return true;
    }
    if (buf_.size() - start_ > max_line_)
      throw InputError(what_ + " '" + path_ + "' line " + std::to_string(line_no_ + 1) +
                       " is longer than " +
                       (max_line_ % (1 << 20) == 0 ? std::to_string(max_line_ >> 20) + " MB"
                                                   : std::to_string(max_line_) + " bytes") +
                       ": not a text log");
    scanned = buf_.size() - start_;  // offset from start_, which fill() makes 0
    if (!fill()) break;
  }
  if (start_ >= buf_.size()) return false;
  ++line_no_;
  *line = std::string_view(buf_).substr(start_);
  start_ = buf_.size();
  return true;
}

uint64_t LineReader::file_offset() const {
  const z_off_t offset = gzoffset(file_.get());
  return offset > 0 ? static_cast<uint64_t>(offset) : 0;
}

std::string read_file_head(const std::string& path, size_t max_bytes) {
  GzHandle f = open_gz(path, "input log");
  std::string head(max_bytes, '\0');
  const int got = gzread(f.get(), head.data(), static_cast<unsigned>(max_bytes));
  head.resize(got > 0 ? static_cast<size_t>(got) : 0);
  return head;
}

void split_fields(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  auto blank = [](char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' ||
           c == '\f';
  };
  size_t i = 0;
  const size_t n = line.size();
  while (i < n) {
    while (i < n && blank(line[i])) ++i;
    const size_t start = i;
    while (i < n && !blank(line[i])) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
}

bool parse_double(std::string_view field, double& value) {
  const char* first = field.data();
  const char* last = first + field.size();
  // from_chars rejects a leading '+', which some writers emit.
  if (first != last && *first == '+') {
    ++first;
    if (first != last && *first == '-') return false;
  }
  const auto res = std::from_chars(first, last, value);
  return res.ec == std::errc() && res.ptr == last && first != last;
}

bool parse_int(std::string_view field, long& value) {
  const char* first = field.data();
  const char* last = first + field.size();
  const auto res = std::from_chars(first, last, value);
  return res.ec == std::errc() && res.ptr == last && first != last;
}

}  // namespace hmt::io::detail

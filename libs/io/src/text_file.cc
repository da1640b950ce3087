#include "text_file.h"

#include <zlib.h>

#include <charconv>
#include <memory>

#include "hmt/common/error.h"
#include "hmt/common/files.h"

namespace hmt::io::detail {
namespace {

struct GzCloser {
  void operator()(gzFile_s* f) const { gzclose(f); }
};
using GzHandle = std::unique_ptr<gzFile_s, GzCloser>;

GzHandle open_gz(const std::string& path, const std::string& what) {
  GzHandle f(gzopen(path.c_str(), "rb"));
  if (!f) throw InputError("cannot open " + what + " '" + path + "'");
  gzbuffer(f.get(), 1 << 17);
  return f;
}

}  // namespace

std::string read_text_file(const std::string& path, const std::string& what) {
  require_readable_file(path, what);
  GzHandle f = open_gz(path, what);
  std::string text;
  char buf[1 << 16];
  for (;;) {
    const int got = gzread(f.get(), buf, sizeof(buf));
    if (got > 0) {
      text.append(buf, static_cast<size_t>(got));
      continue;
    }
    int errnum = Z_OK;
    const char* msg = gzerror(f.get(), &errnum);
    if (got < 0 || (errnum != Z_OK && errnum != Z_STREAM_END)) {
      std::string text = msg ? msg : "error";
      // zlib prefixes the file name, which the message already has.
      if (text.compare(0, path.size() + 2, path + ": ") == 0)
        text.erase(0, path.size() + 2);
      throw InputError(what + " '" + path + "' is a damaged gzip file (zlib: " +
                       text + ")");
    }
    break;
  }
  return text;
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

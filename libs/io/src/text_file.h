// Whole-file reading for the text formats (CARMEN, TUM), gzip or plain.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace hmt::io::detail {

// The decompressed content of `path` (plain files are read as they are).
// `what` names the file in messages ("CARMEN log", "TUM file"). Throws
// hmt::InputError if the file is missing, not a regular file, or a damaged
// gzip stream.
std::string read_text_file(const std::string& path, const std::string& what);

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

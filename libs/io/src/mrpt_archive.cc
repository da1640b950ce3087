#include "mrpt_archive.h"

#include <algorithm>
#include <cstring>

namespace hmt::io::detail {
namespace {

constexpr uint8_t kEndFlag = 0x88;
constexpr uint8_t kNewFormatBit = 0x80;
// MRPT refuses longer class names as a sign of a corrupted stream.
constexpr size_t kMaxClassName = 120;

}  // namespace

void ArchiveReader::read_bytes(void* out, size_t count) {
  if (in_.read(out, count) != count)
    throw ArchiveError("the data ends inside an object");
}

void ArchiveReader::skip(uint64_t count) {
  char buf[4096];
  while (count > 0) {
    const size_t n = static_cast<size_t>(std::min<uint64_t>(count, sizeof(buf)));
    read_bytes(buf, n);
    count -= n;
  }
}

std::string ArchiveReader::string() {
  std::vector<char> chars;
  array(u32(), chars);
  return std::string(chars.begin(), chars.end());
}

ObjectHeader ArchiveReader::header() {
  ObjectHeader h;
  uint8_t len = u8();
  if (!(len & kNewFormatBit)) {
    // Old format: the length was a little-endian uint32.
    uint8_t rest[3];
    read_bytes(rest, 3);
    if (rest[0] || rest[1] || rest[2])
      throw ArchiveError("malformed object header");
    h.old_format = true;
  }
  len &= 0x7f;
  if (len > kMaxClassName) throw ArchiveError("class name too long");
  h.class_name.resize(len);
  read_bytes(h.class_name.data(), len);
  if (h.old_format) {
    const int32_t v = i32();
    if (v < 0 || v >= 255) throw ArchiveError("bad object version");
    h.version = static_cast<uint8_t>(v);
  } else if (!h.is_null()) {
    h.version = u8();
    // MRPT holds the version in an int8_t and rejects negative ones.
    if (h.version & 0x80) throw ArchiveError("bad object version");
  }
  return h;
}

void ArchiveReader::end(const ObjectHeader& h) {
  if (h.old_format) return;
  if (u8() != kEndFlag)
    throw ArchiveError("object of class " + h.class_name +
                       " does not end where it should");
}

void ArchiveWriter::bytes(const void* data, size_t count) {
  if (ok_ && count > 0) ok_ = out_.write(data, count);
}

void ArchiveWriter::string(const std::string& s) {
  u32(static_cast<uint32_t>(s.size()));
  bytes(s.data(), s.size());
}

void ArchiveWriter::begin_object(const char* class_name, uint8_t version) {
  const size_t len = std::strlen(class_name);
  u8(static_cast<uint8_t>(len | kNewFormatBit));
  bytes(class_name, len);
  u8(version);
}

}  // namespace hmt::io::detail

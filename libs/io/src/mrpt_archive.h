// MRPT's binary serialization (mrpt::serialization::CArchive as of MRPT 2.x),
// read and written without MRPT: plain values in little-endian byte order,
// strings and arrays prefixed by a 32-bit count, and objects framed as
//   [name length | 0x80] [class name] [version byte] fields... [0x88]
// Files from MRPT < 0.5.5 frame objects as
//   [name length as uint32] [class name] [version as int32] fields...
// with no end flag; both are read. A null object is named "nullptr" and has
// no version byte.
//
// Nothing says how long an object is: a reader must know the layout of every
// class it meets (rawlog_objects.h knows the rawlog's laser/odometry ones).
#pragma once

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "gz_stream.h"

namespace hmt::io::detail {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "the archive code copies MRPT's little-endian values as is");

// The data cannot be read as what it claims to be, or it ended too soon; the
// caller tells the two apart by whether input is left (GzInputStream).
struct ArchiveError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct ObjectHeader {
  std::string class_name;
  uint8_t version = 0;      // meaningless for a null object
  bool old_format = false;  // MRPT < 0.5.5: no end flag
  bool is_null() const { return class_name == "nullptr"; }
};

class ArchiveReader {
 public:
  explicit ArchiveReader(GzInputStream& in) : in_(in) {}

  // Exactly `count` bytes, or ArchiveError.
  void read_bytes(void* out, size_t count);
  void skip(uint64_t count);

  // One value, its bytes as stored (little-endian, IEEE-754).
  template <typename T>
  T value() {
    T v;
    read_bytes(&v, sizeof v);
    return v;
  }
  uint8_t u8() { return value<uint8_t>(); }
  bool boolean() { return u8() != 0; }  // any non-zero byte is true
  int32_t i32() { return value<int32_t>(); }
  uint32_t u32() { return value<uint32_t>(); }
  uint64_t u64() { return value<uint64_t>(); }
  float f32() { return value<float>(); }
  double f64() { return value<double>(); }
  std::string string();  // uint32 length + bytes

  // `count` values straight from the stream (MRPT's ReadBufferFixEndianness).
  // The vector grows as the data arrives, so a corrupt count costs at most
  // as much memory as the file really holds before the read fails.
  template <typename T>
  void array(uint64_t count, std::vector<T>& out) {
    out.clear();
    constexpr uint64_t kChunk = (1 << 16) / sizeof(T);
    while (count > 0) {
      const size_t n = static_cast<size_t>(std::min(count, kChunk));
      const size_t old = out.size();
      out.resize(old + n);
      read_bytes(out.data() + old, n * sizeof(T));
      count -= n;
    }
  }

  // The header of the next object (ArchiveError for a malformed one).
  ObjectHeader header();
  // The end flag that closes an object read under `h` (none in the old
  // format).
  void end(const ObjectHeader& h);

 private:
  GzInputStream& in_;
};

class ArchiveWriter {
 public:
  explicit ArchiveWriter(GzOutputStream& out) : out_(out) {}

  void bytes(const void* data, size_t count);
  void u8(uint8_t v) { bytes(&v, 1); }
  void boolean(bool v) { u8(v ? 1 : 0); }
  void i32(int32_t v) { bytes(&v, 4); }
  void u32(uint32_t v) { bytes(&v, 4); }
  void u64(uint64_t v) { bytes(&v, 8); }
  void f32(float v) { bytes(&v, 4); }
  void f64(double v) { bytes(&v, 8); }
  void string(const std::string& s);

  // Object framing as MRPT 2.x writes it (new format, end flag 0x88).
  void begin_object(const char* class_name, uint8_t version);
  void end_object() { u8(0x88); }

  // False once a write failed.
  bool ok() const { return ok_; }

 private:
  GzOutputStream& out_;
  bool ok_ = true;
};

}  // namespace hmt::io::detail

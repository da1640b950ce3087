// Hand-made MRPT archive bytes, for object versions the installed MRPT no
// longer writes (it reads them all): each test builds the layout MRPT's
// deserializer expects and checks that MRPT and the native reader agree.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace hmt::io::testing_util {

class Bytes {
 public:
  Bytes& u8(uint8_t v) { return raw(&v, 1); }
  Bytes& boolean(bool v) { return u8(v ? 1 : 0); }
  Bytes& i32(int32_t v) { return raw(&v, 4); }
  Bytes& u32(uint32_t v) { return raw(&v, 4); }
  Bytes& u64(uint64_t v) { return raw(&v, 8); }
  Bytes& f32(float v) { return raw(&v, 4); }
  Bytes& f64(double v) { return raw(&v, 8); }
  Bytes& str(const std::string& s) {
    u32(static_cast<uint32_t>(s.size()));
    return raw(s.data(), s.size());
  }
  Bytes& raw(const void* p, size_t n) {
    data_.append(static_cast<const char*>(p), n);
    return *this;
  }
  Bytes& add(const Bytes& b) { return raw(b.data_.data(), b.data_.size()); }
  // An object: header (as MRPT >= 0.5.5 writes it, or the old one), the
  // body, and the end flag (new format only).
  Bytes& obj(const std::string& name, int version, const Bytes& body,
             bool old_format = false) {
    if (old_format) {
      u32(static_cast<uint32_t>(name.size()));
      raw(name.data(), name.size());
      i32(version);
      return add(body);
    }
    u8(static_cast<uint8_t>(name.size() | 0x80));
    raw(name.data(), name.size());
    u8(static_cast<uint8_t>(version));
    add(body);
    return u8(0x88);
  }
  Bytes& null_obj() {
    u8(0x80 | 7);
    raw("nullptr", 7);
    return u8(0x88);
  }
  const std::string& bytes() const { return data_; }

 private:
  std::string data_;
};

}  // namespace hmt::io::testing_util

// Builds the container of topology and HMT map files (topology_file.h: a
// 40-byte header with sizes and CRCs, then the deflated payload) around a
// payload, so that the fuzzer's mutations reach the payload decoder instead
// of stopping at the checksums. The header layout is the documented one;
// decoding is left entirely to the library.
#pragma once

#include <zlib.h>

#include <cstdint>
#include <string>

#include "fuzz_support.h"

namespace hmt::fuzz {

inline void put_le(std::string& out, uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}

inline uint32_t crc_of(const std::string& s) {
  return static_cast<uint32_t>(
      crc32_z(crc32_z(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(s.data()), s.size()));
}

inline std::string wrap_payload(const char (&magic)[8], uint32_t version,
                                const std::string& payload) {
  uLongf stored = compressBound(payload.size());
  std::string deflated(stored, '\0');
  check(compress2(reinterpret_cast<Bytef*>(deflated.data()), &stored,
                  reinterpret_cast<const Bytef*>(payload.data()), payload.size(),
                  Z_BEST_SPEED) == Z_OK,
        "zlib cannot deflate the payload");
  deflated.resize(stored);
  std::string file(magic, 8);
  put_le(file, version, 4);
  put_le(file, 0, 4);  // flags
  put_le(file, payload.size(), 8);
  put_le(file, deflated.size(), 8);
  put_le(file, crc_of(payload), 4);
  put_le(file, crc_of(file), 4);
  return file + deflated;
}

}  // namespace hmt::fuzz

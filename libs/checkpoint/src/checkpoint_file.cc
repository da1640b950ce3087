// The checkpoint file: header, checksums, identity, then the state
// (state_io.cc). The payload is streamed to the file and its CRC computed on
// the way, so saving never holds a second copy of the state in memory;
// reading checks the CRC in one pass over the file before parsing it in a
// second, so a corrupt file is reported as such rather than parsed.
#include <zlib.h>

#include <cereal/types/string.hpp>

#include <array>
#include <cstring>
#include <fstream>
#include <streambuf>

#include "hmt/checkpoint/checkpoint.h"
#include "hmt/common/error.h"
#include "hmt/common/files.h"
#include "hmt/version.h"
#include "state_io.h"

namespace hmt::checkpoint {
namespace {

// Forwards to another stream buffer, counting bytes and updating a CRC-32.
class CrcBuf : public std::streambuf {
 public:
  explicit CrcBuf(std::streambuf* out) : out_(out) {}
  uint32_t crc() const { return crc_; }
  uint64_t size() const { return size_; }

 protected:
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    add(s, n);
    return out_->sputn(s, n);
  }
  int_type overflow(int_type c) override {
    if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
    const char ch = traits_type::to_char_type(c);
    add(&ch, 1);
    return out_->sputc(ch);
  }

 private:
  void add(const char* s, std::streamsize n) {
    // zlib's crc32 takes an unsigned int length: feed large blocks in parts.
    while (n > 0) {
      const uInt part = static_cast<uInt>(std::min<std::streamsize>(n, 1 << 30));
      crc_ = static_cast<uint32_t>(crc32(crc_, reinterpret_cast<const Bytef*>(s), part));
      s += part;
      n -= part;
      size_ += part;
    }
  }
  std::streambuf* out_;
  uint32_t crc_ = 0;
  uint64_t size_ = 0;
};

void put_u32(char* at, uint32_t v) {
  for (int i = 0; i < 4; ++i) at[i] = static_cast<char>((v >> (8 * i)) & 0xff);
}
void put_u64(char* at, uint64_t v) {
  for (int i = 0; i < 8; ++i) at[i] = static_cast<char>((v >> (8 * i)) & 0xff);
}
uint32_t get_u32(const char* at) {
  uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(at[i]);
  return v;
}
uint64_t get_u64(const char* at) {
  uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(at[i]);
  return v;
}

using Header = std::array<char, kCheckpointHeaderSize>;

Header make_header(uint64_t payload_size, uint32_t payload_crc) {
  Header h{};
  std::memcpy(h.data(), kCheckpointMagic, 8);
  put_u32(h.data() + 8, kCheckpointFormatVersion);
  put_u32(h.data() + 12, 0);
  put_u64(h.data() + 16, payload_size);
  put_u32(h.data() + 24, payload_crc);
  put_u32(h.data() + 28, static_cast<uint32_t>(
                             crc32(0, reinterpret_cast<const Bytef*>(h.data()), 28)));
  return h;
}

template <class A>
void identity_io(A& ar, RunIdentity& id) {
  ar(id.version, id.config, id.input, id.steps, id.log_crc, id.report);
}

// Opens the file and checks everything but the state's own consistency;
// leaves the stream at the start of the payload.
std::ifstream open_checked(const std::string& path) {
  require_readable_file(path, "checkpoint");
  std::ifstream in(path, std::ios::binary);
  const auto bad = [&](const std::string& why) {
    return InputError("checkpoint '" + path + "': " + why);
  };
  Header h{};
  in.read(h.data(), h.size());
  if (in.gcount() != static_cast<std::streamsize>(h.size()))
    throw bad("truncated (shorter than its header)");
  if (std::memcmp(h.data(), kCheckpointMagic, 8) != 0)
    throw bad("not an hmt-slam checkpoint (wrong magic)");
  if (get_u32(h.data() + 28) !=
      static_cast<uint32_t>(crc32(0, reinterpret_cast<const Bytef*>(h.data()), 28)))
    throw bad("corrupt header (checksum mismatch)");
  const uint32_t version = get_u32(h.data() + 8);
  if (version != kCheckpointFormatVersion)
    throw bad("format version " + std::to_string(version) + ", this hmt-slam reads version " +
              std::to_string(kCheckpointFormatVersion));
  const uint64_t size = get_u64(h.data() + 16);
  const uint32_t want = get_u32(h.data() + 24);
  std::vector<char> buf(1 << 20);
  uint64_t seen = 0;
  uint32_t crc = 0;
  while (in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    const std::streamsize got = in.gcount();
    if (got <= 0) break;
    crc = static_cast<uint32_t>(crc32(crc, reinterpret_cast<const Bytef*>(buf.data()),
                                      static_cast<uInt>(got)));
    seen += static_cast<uint64_t>(got);
  }
  if (seen < size)
    throw bad("truncated: " + std::to_string(seen) + " of " + std::to_string(size) +
              " payload bytes");
  if (seen > size) throw bad("trailing bytes after the payload");
  if (crc != want) throw bad("corrupt payload (checksum mismatch)");
  in.clear();
  in.seekg(static_cast<std::streamoff>(kCheckpointHeaderSize));
  return in;
}

RunIdentity read_identity_from(cereal::BinaryInputArchive& ar, const std::string& path) {
  RunIdentity id;
  identity_io(ar, id);
  if (id.version != HMT_VERSION)
    throw InputError("checkpoint '" + path + "' was written by hmt-slam " + id.version +
                     "; this is hmt-slam " HMT_VERSION);
  return id;
}

}  // namespace

uint32_t log_fingerprint(uint32_t crc, const LogStep& step) {
  const auto add = [&](const void* p, size_t n) {
    crc = static_cast<uint32_t>(crc32(crc, static_cast<const Bytef*>(p), static_cast<uInt>(n)));
  };
  add(&step.timestamp, sizeof step.timestamp);
  const double u[3] = {step.odometry_increment.x, step.odometry_increment.y,
                       step.odometry_increment.theta};
  add(u, sizeof u);
  if (!step.scan.ranges.empty())
    add(step.scan.ranges.data(), step.scan.ranges.size() * sizeof(float));
  return crc;
}

void save(const std::string& path, const RunIdentity& identity,
          const framework::HmtSystem& system) {
  write_file_atomically(path, [&](std::ostream& os) {
    const Header placeholder{};
    os.write(placeholder.data(), placeholder.size());
    CrcBuf buf(os.rdbuf());
    {
      std::ostream payload(&buf);
      cereal::BinaryOutputArchive ar(payload);
      RunIdentity id = identity;
      id.version = HMT_VERSION;
      identity_io(ar, id);
      write_state(ar, system);
      payload.flush();
      if (!payload) return;  // os is in error too: write_file_atomically reports it
    }
    const Header h = make_header(buf.size(), buf.crc());
    os.seekp(0);
    os.write(h.data(), h.size());
  });
}

RunIdentity read_identity(const std::string& path) {
  std::ifstream in = open_checked(path);
  cereal::BinaryInputArchive ar(in);
  try {
    return read_identity_from(ar, path);
  } catch (const cereal::Exception& e) {
    throw InputError("checkpoint '" + path + "': unreadable identity (" + e.what() + ")");
  }
}

RunIdentity load(const std::string& path, framework::HmtSystem& system) {
  std::ifstream in = open_checked(path);
  cereal::BinaryInputArchive ar(in);
  RunIdentity id;
  try {
    id = read_identity_from(ar, path);
    read_state(ar, system);
  } catch (const cereal::Exception& e) {
    throw InputError("checkpoint '" + path + "': unreadable state (" + e.what() + ")");
  }
  if (in.peek() != std::ifstream::traits_type::eof())
    throw InputError("checkpoint '" + path + "': bytes left over after the state");
  return id;
}

}  // namespace hmt::checkpoint

// The HMT map file decoder (hmt_map.bin, decode_session) on arbitrary bytes.
//
// The first input byte chooses what the rest is: even, a whole file; odd, a
// payload, wrapped in a valid container (format version 2 if bit 1 is set,
// else the current one) so that mutations reach the payload's own checks.
#include "container.h"
#include "fuzz_support.h"
#include "hmt/common/error.h"
#include "hmt/topology/topology_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  std::string rest(reinterpret_cast<const char*>(data) + 1, size - 1);
  if (data[0] & 1)
    rest = hmt::fuzz::wrap_payload(hmt::topology::kSessionMagic,
                                   (data[0] & 2) ? hmt::topology::kOldestSessionFormatVersion
                                                 : hmt::topology::kSessionFormatVersion,
                                   rest);
  try {
    const hmt::topology::Session s = hmt::topology::decode_session(rest, "fuzz");
    // What loaded must save and load back to the same bytes.
    const std::string again = hmt::topology::encode_session(s);
    hmt::fuzz::check(hmt::topology::encode_session(hmt::topology::decode_session(again, "again")) ==
                         again,
                     "a loaded HMT map file does not round-trip");
  } catch (const hmt::InputError&) {
  }
  return 0;
}

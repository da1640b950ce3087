// The topology file decoder (decode_topology) on arbitrary bytes.
//
// The first input byte chooses what the rest is: even, a whole file (magic,
// header checks, checksums, inflation); odd, a payload, wrapped in a valid
// container first so that mutations reach the payload's own checks.
#include "container.h"
#include "fuzz_support.h"
#include "hmt/common/error.h"
#include "hmt/topology/topology_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  std::string rest(reinterpret_cast<const char*>(data) + 1, size - 1);
  if (data[0] & 1)
    rest = hmt::fuzz::wrap_payload(hmt::topology::kTopologyMagic,
                                   hmt::topology::kTopologyFormatVersion, rest);
  try {
    const hmt::topology::TopologySnapshot snap = hmt::topology::decode_topology(rest, "fuzz");
    // What loaded must save and load back to the same bytes.
    const std::string again = hmt::topology::encode_topology(snap.map, snap.hypotheses);
    const hmt::topology::TopologySnapshot back = hmt::topology::decode_topology(again, "again");
    hmt::fuzz::check(hmt::topology::encode_topology(back.map, back.hypotheses) == again,
                     "a loaded topology does not round-trip");
  } catch (const hmt::InputError&) {
  }
  return 0;
}

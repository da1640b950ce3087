// SSO values of keyframe pairs, kept across SsoGraphs that see the same
// keyframes again.
//
// Why: TSBI's area check (tsbi::TransitionModel::same_area) builds a small
// SsoGraph at every event, for every candidate area of every hypothesis,
// from the area's keyframes nearest to the robot; those keyframes' pairs
// come back from one event to the next: on Intel they were two thirds of
// the check's scan matches, three quarters of them repeats. A pair's SSO
// is a pure function of the two keyframes (poses, scans) and the SSO
// options, so a cached value is the value recomputing would give, to the
// bit (scan_sso is symmetric in its two scans to the bit as well), and a
// graph built with the cache is the graph built without it.
//
// Keyframes are identified by content (keyframe_key: every bit of the pose,
// of the scan and of the options, hashed to 64 bits), not by address or
// index, since areas are copied on write between hypotheses and two
// hypotheses' areas of the same id may hold different keyframes.
//
// Bounded: when `capacity` pairs are held, the cache starts afresh (cheaper
// than an LRU list, and values are recomputed identically). Thread-safe.
#pragma once

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <optional>
#include <unordered_map>
#include <utility>

#include "hmt/area/area_options.h"
#include "hmt/area/keyframe.h"

namespace hmt::area {

// A 64-bit fingerprint of everything a keyframe's SSO with another depends
// on: the pose (mean and covariance), the scan (timestamp, geometry, ranges,
// validity flags) and the SSO options.
uint64_t keyframe_key(const Keyframe& keyframe, const SsoOptions& options);

class SsoPairCache {
 public:
  explicit SsoPairCache(size_t capacity = kDefaultCapacity);

  // The SSO of the pair with these keys (either order), if held.
  std::optional<double> find(uint64_t a, uint64_t b) const;
  void put(uint64_t a, uint64_t b, double sso);

  size_t size() const;
  size_t hits() const;
  size_t misses() const;

  // About 64 bytes a pair: at most some 4 MB. The area check's pairs of
  // a whole run fit: 19 700 on Intel, 21 400 on the Infinite Corridor.
  static constexpr size_t kDefaultCapacity = size_t{1} << 16;

 private:
  struct PairHash {
    size_t operator()(const std::pair<uint64_t, uint64_t>& k) const;
  };
  static std::pair<uint64_t, uint64_t> ordered(uint64_t a, uint64_t b) {
    return a < b ? std::make_pair(a, b) : std::make_pair(b, a);
  }

  size_t capacity_;
  mutable std::mutex mutex_;
  std::unordered_map<std::pair<uint64_t, uint64_t>, double, PairHash> values_;
  mutable size_t hits_ = 0, misses_ = 0;
};

}  // namespace hmt::area

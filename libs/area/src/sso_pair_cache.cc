#include "hmt/area/sso_pair_cache.h"

#include <cstring>
#include <stdexcept>

#include "hmt/common/random.h"

namespace hmt::area {
namespace {

// Folds 64-bit words into a running hash with splitmix64's finaliser.
class Hasher {
 public:
  void word(uint64_t w) { h_ = mix_seed(h_ ^ w); }
  void real(double v) {
    uint64_t w;
    std::memcpy(&w, &v, sizeof w);
    word(w);
  }
  void real(float v) {
    uint32_t w;
    std::memcpy(&w, &v, sizeof w);
    word(w);
  }
  void pose(const Pose2D& p) {
    real(p.x);
    real(p.y);
    real(p.theta);
  }
  uint64_t value() const { return h_; }

 private:
  uint64_t h_ = 0x243f6a8885a308d3ULL;
};

}  // namespace

uint64_t keyframe_key(const Keyframe& kf, const SsoOptions& o) {
  Hasher h;
  h.real(o.delta);
  h.word(o.use_probabilistic ? 1 : 0);
  h.real(o.beta);
  h.real(o.range_std);
  h.real(o.bearing_std);
  h.real(o.gate);
  h.real(o.descriptor_threshold);
  h.pose(kf.pose.mean);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) h.real(kf.pose.cov(r, c));
  const LaserScan& s = kf.scan;
  h.real(s.timestamp);
  h.real(s.angle_min);
  h.real(s.angle_increment);
  h.real(s.max_range);
  h.pose(s.sensor_pose);
  h.word(s.ranges.size());
  // Two ranges a word (their bits, so -0 and NaN payloads count too).
  for (size_t i = 0; i < s.ranges.size(); i += 2) {
    uint32_t lo, hi = 0;
    std::memcpy(&lo, &s.ranges[i], sizeof lo);
    if (i + 1 < s.ranges.size()) std::memcpy(&hi, &s.ranges[i + 1], sizeof hi);
    h.word(static_cast<uint64_t>(hi) << 32 | lo);
  }
  h.word(s.valid.size());
  for (size_t i = 0; i < s.valid.size(); i += 8) {
    uint64_t w = 0;
    for (size_t k = 0; k < 8 && i + k < s.valid.size(); ++k)
      w |= static_cast<uint64_t>(s.valid[i + k]) << (8 * k);
    h.word(w);
  }
  return h.value();
}

size_t SsoPairCache::PairHash::operator()(const std::pair<uint64_t, uint64_t>& k) const {
  return static_cast<size_t>(mix_seed(k.first ^ mix_seed(k.second)));
}

SsoPairCache::SsoPairCache(size_t capacity) : capacity_(capacity) {
  if (capacity == 0) throw std::invalid_argument("SsoPairCache: capacity 0");
}

std::optional<double> SsoPairCache::find(uint64_t a, uint64_t b) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = values_.find(ordered(a, b));
  if (it == values_.end()) {
    ++misses_;
    return std::nullopt;
  }
  ++hits_;
  return it->second;
}

void SsoPairCache::put(uint64_t a, uint64_t b, double sso) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (values_.size() >= capacity_) values_.clear();
  values_[ordered(a, b)] = sso;
}

size_t SsoPairCache::size() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return values_.size();
}

size_t SsoPairCache::hits() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return hits_;
}

size_t SsoPairCache::misses() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return misses_;
}

}  // namespace hmt::area

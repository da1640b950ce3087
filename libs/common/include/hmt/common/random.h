// The one seeded random generator, passed down explicitly. Its samplers are
// written here (not std::normal_distribution) so that the same seed gives the
// same numbers with any standard library.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>

namespace hmt::checkpoint {
struct Access;  // hmt/checkpoint/checkpoint.h
}  // namespace hmt::checkpoint

namespace hmt {

class Random {
  // Checkpoints save and restore every member, bit for bit.
  friend struct hmt::checkpoint::Access;

 public:
  explicit Random(uint64_t seed = 1) : engine_(seed) {}

  // Uniform in [0, 1).
  double uniform() {
    return static_cast<double>(engine_() >> 11) * (1.0 / 9007199254740992.0);
  }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Standard normal by Box-Muller (one value per call, the pair's twin kept).
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u1 = uniform();
    while (u1 <= 0.0) u1 = uniform();
    const double u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(2.0 * M_PI * u2);
    has_spare_ = true;
    return r * std::cos(2.0 * M_PI * u2);
  }
  double normal(double mean, double sigma) { return mean + sigma * normal(); }
  uint64_t next_u64() { return engine_(); }

 private:
  std::mt19937_64 engine_;
  bool has_spare_ = false;
  double spare_ = 0.0;
};

// Decorrelates a value into a seed (splitmix64's finaliser): streams derived
// from (seed, step, index) this way are independent for practical purposes.
inline uint64_t mix_seed(uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

}  // namespace hmt

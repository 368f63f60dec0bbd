// A random number generator that gives the same numbers on every platform and compiler:
// xoshiro256** seeded through splitmix64, with its own uniform and normal deviates (std::
// distributions are implementation-defined, so synthetic data and tests would differ between
// standard libraries). Not for cryptography.
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>

namespace splatkit {

// One step of splitmix64: advances `state` and returns a well-mixed 64-bit value.
constexpr uint64_t splitmix64(uint64_t& state) {
  uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

class DeterministicRng {
 public:
  // `stream` selects an independent sequence for the same seed (one per patch, one for noise...).
  explicit DeterministicRng(uint64_t seed, uint64_t stream = 0) {
    uint64_t sm = seed;
    uint64_t mixed = splitmix64(sm) ^ (stream * 0xD1B54A32D192ED03ull);
    for (uint64_t& word : s_) word = splitmix64(mixed);
  }

  uint64_t next() {
    const uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }

  // Uniform in [0, 1), 53 random bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Uniform in [0, 1) as a float, 24 random bits (every value exactly representable).
  float uniformf() { return static_cast<float>(next() >> 40) * 0x1.0p-24f; }

  // Standard normal deviate (Box–Muller; both values of a pair are used).
  double normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const double u1 = 1.0 - uniform();  // (0, 1]: log stays finite
    const double u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    const double a = 2.0 * std::numbers::pi * u2;
    spare_ = r * std::sin(a);
    has_spare_ = true;
    return r * std::cos(a);
  }

 private:
  static constexpr uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

  uint64_t s_[4];
  double spare_ = 0;
  bool has_spare_ = false;
};

}  // namespace splatkit

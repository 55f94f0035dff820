// A portable random source: SplitMix64 (Steele, Lea, Flood 2014). std::shuffle and the standard
// distributions differ between standard libraries, so everything seeded in occsweep goes through this.
#pragma once

#include <cmath>
#include <cstdint>

namespace occsweep {

class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}

  /// The next 64 random bits.
  [[nodiscard]] std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }

  /// Uniform in [0, 1) with 53 random bits.
  [[nodiscard]] double uniform() { return double(next() >> 11) * 0x1.0p-53; }

  /// Uniform integer in [0, bound) by rejection (no modulo bias), bound > 0.
  [[nodiscard]] std::uint64_t below(std::uint64_t bound) {
    const std::uint64_t limit = UINT64_MAX - UINT64_MAX % bound;
    std::uint64_t r;
    do r = next();
    while (r >= limit);
    return r % bound;
  }

  /// Standard normal by Box-Muller (one value per call, the second discarded for simplicity).
  [[nodiscard]] double gaussian() {
    double u1;
    do u1 = uniform();
    while (u1 <= 0.0);
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }

 private:
  std::uint64_t state_;
};

}  // namespace occsweep

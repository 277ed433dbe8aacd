// scenes/rng.hpp — the one random generator of scenes, stress cases, tests and benchmarks.
//
// Takes: a 64-bit seed. Gives: splitmix64 (Steele, Lea, Flood 2014): tiny, fast, and the same
// sequence on every standard library, so a seed names the same scene or case everywhere (the
// std:: distributions are implementation-defined).
#pragma once

#include <cmath>
#include <cstdint>

#include "mosaic/types.hpp"

namespace mosaic {

class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}

  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, 1) from 53 random bits.
  double unit() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * unit(); }
  /// Uniform integer in [lo, hi].
  int range(int lo, int hi) {
    return lo + static_cast<int>(next() % static_cast<std::uint64_t>(hi - lo + 1));
  }
  bool chance(double p) { return unit() < p; }
  /// Log-uniform in [lo, hi] (both > 0).
  double log_uniform(double lo, double hi) { return std::exp(uniform(std::log(lo), std::log(hi))); }
  /// Uniform depth in [0, 1) on a 2^-24 grid: exact in float, and never 1 (the clear depth,
  /// which the default depth test would reject).
  float depth() { return static_cast<float>(next() >> 40) * 0x1.0p-24f; }
  std::uint8_t byte() { return static_cast<std::uint8_t>(next()); }
  /// A random opaque colour.
  Rgba8 color() {
    const std::uint64_t r = next();
    return {static_cast<std::uint8_t>(r), static_cast<std::uint8_t>(r >> 8),
            static_cast<std::uint8_t>(r >> 16), 255};
  }

 private:
  std::uint64_t state_;
};

}  // namespace mosaic

// Counter-based random numbers: every sample is a pure function of (seed, stream, index), so ray
// generation is deterministic whatever the order or thread count.
#pragma once

#include <cstdint>

namespace hrpp {

/// SplitMix64 finalizer (Steele, Lea, Flood 2014): a strong 64-bit mixing function.
inline uint64_t mix64(uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/// Uniform float in [0, 1) from the 24 top bits of a hash of the arguments.
inline float uniform01(uint64_t seed, uint64_t a, uint64_t b, uint64_t c = 0) {
  uint64_t h = mix64(seed ^ mix64(a ^ mix64(b ^ mix64(c))));
  return static_cast<float>(h >> 40) * (1.0f / 16777216.0f);
}

}  // namespace hrpp

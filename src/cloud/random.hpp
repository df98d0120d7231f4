// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Counter-based uniform random numbers: reproducible regardless of thread count
// and identical on every platform (std:: distributions are not).
#include <cstdint>

namespace vrsph::detail {

inline std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

/// Uniform in [0, 1) from (seed, stream, counter).
inline double uniform01(std::uint64_t seed, std::uint64_t stream, std::uint64_t counter) {
  const std::uint64_t h = splitmix64(splitmix64(seed ^ splitmix64(stream)) + counter);
  return static_cast<double>(h >> 11) * 0x1.0p-53;
}

}  // namespace vrsph::detail

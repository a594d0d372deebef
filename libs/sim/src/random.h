#pragma once
// Deterministic randomness: every random quantity of the simulator is a hash of its
// inputs (seed, frame, pixel, surface cell), never of thread scheduling or call order.
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace gmc::sim::detail {

/// SplitMix64 finaliser.
inline std::uint64_t mix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}
inline std::uint64_t hash(std::uint64_t a, std::uint64_t b, std::uint64_t c = 0, std::uint64_t d = 0) {
  return mix(a ^ mix(b ^ mix(c ^ mix(d))));
}
/// Uniform in [0, 1) from 53 bits of a hash.
inline double unit(std::uint64_t h) { return static_cast<double>(h >> 11) * (1.0 / 9007199254740992.0); }
/// Standard normal from one hash (Box-Muller).
inline double gaussian(std::uint64_t h) {
  const double u1 = std::max(unit(h), 1e-12), u2 = unit(mix(h));
  return std::sqrt(-2 * std::log(u1)) * std::cos(2 * M_PI * u2);
}

/// Small sequential generator for building the scene (order fixed by the code).
struct Rng {
  std::uint64_t state;
  double uniform(double a, double b) { return a + (b - a) * unit(state = mix(state)); }
  std::uint64_t next() { return state = mix(state + 1); }
};

}  // namespace gmc::sim::detail

#pragma once
// Counter-based random numbers: the normal deviates of element e at step s are a hash of (seed,
// s, e), so a forecast gives the same elements on any number of threads and in any order.

#include <cmath>
#include <cstdint>

namespace farfield {

// SplitMix64's finaliser: a bijective mix of all 64 bits.
inline std::uint64_t mix64(std::uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

struct CounterRandom {
  std::uint64_t key = 0;
  CounterRandom(std::uint64_t seed, std::uint64_t step, std::uint64_t element, std::uint64_t salt)
      : key(mix64(mix64(mix64(seed) ^ step) ^ element) ^ salt) {}
  // A uniform in (0, 1) from the 53 high bits of the next draw.
  double uniform() {
    key = mix64(key);
    return (double(key >> 11) + 0.5) * (1.0 / 9007199254740992.0);
  }
  // Two independent standard normal deviates (Box-Muller).
  void normal_pair(double& a, double& b) {
    const double r = std::sqrt(-2.0 * std::log(uniform()));
    const double phi = 6.283185307179586 * uniform();
    a = r * std::cos(phi);
    b = r * std::sin(phi);
  }
};

}  // namespace farfield

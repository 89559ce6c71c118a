// Test support: splitmix64, a small portable deterministic generator (the same numbers on every
// platform and standard library), with the few distributions the tests draw from.
#pragma once
#include <cmath>
#include <cstdint>
#include <numbers>

#include "bagdem/vec3.hpp"

namespace bagdem::testing {

struct Rng {
  std::uint64_t s;
  explicit Rng(std::uint64_t seed) : s(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (s += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  double uniform(double a = 0, double b = 1) { return a + (b - a) * (static_cast<double>(next() >> 11) * 0x1.0p-53); }
  double normal() {  // Box-Muller
    const double u = uniform(1e-300, 1), v = uniform();
    return std::sqrt(-2 * std::log(u)) * std::cos(2 * std::numbers::pi * v);
  }
  Vec3 unit() {  // uniform direction (rejection from the cube)
    for (;;) {
      const Vec3 d = draw_vec3([&] { return uniform(-1, 1); });
      const double n = d.norm();
      if (n > 0.1 && n <= 1) return d / n;
    }
  }
};

}  // namespace bagdem::testing

// A seeded random source whose draws are the same on every platform and standard library
// (std::uniform_real_distribution and std::normal_distribution are implementation-defined), so that
// generated data and tests are byte-for-byte reproducible.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>

namespace toolinc {

class Rng {
 public:
  explicit Rng(std::uint32_t seed) : engine_(seed) {}

  // Uniform in [0, 1).
  double uniform() {
    const std::uint64_t hi = engine_() >> 5, lo = engine_() >> 6;  // 53 random bits
    return static_cast<double>((hi << 26) | lo) * (1.0 / 9007199254740992.0);
  }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  std::uint32_t index(std::uint32_t n) { return static_cast<std::uint32_t>(uniform() * n); }

  // Standard normal by Box-Muller (both values used in turn).
  double gaussian() {
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

 private:
  std::mt19937 engine_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace toolinc

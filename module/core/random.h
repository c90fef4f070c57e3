// Deterministic, portable pseudo-random numbers for everything a scene draws from a seed (grid
// jitter, joint-set jitter): the same bits on every machine, compiler and standard library
// (std::uniform_real_distribution differs between libraries). SplitMix64 (Steele, Lea and Flood
// 2014).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace polydem {

/// One SplitMix64 output for the state `z` (a bijective mix of its 64 bits).
inline std::uint64_t splitMix64(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/// A uniform double in [0, 1) from the top 53 bits of `bits`.
inline double unitInterval(std::uint64_t bits) {
  return static_cast<double>(bits >> 11) * 0x1.0p-53;
}

/// A stream of uniform numbers from a seed.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    const std::uint64_t z = splitMix64(state_);
    state_ += 0x9e3779b97f4a7c15ULL;
    return z;
  }
  double uniform() { return unitInterval(next()); }  // in [0, 1)

 private:
  std::uint64_t state_;
};

/// The uniform number in [0, 1) of draw `draw` for item `index` of a seed, independent of every
/// other item's draws: jitter that does not change when items are added or skipped.
inline double uniformAt(std::uint64_t seed, std::int64_t index, std::uint64_t draw) {
  const std::uint64_t item = splitMix64(seed ^ splitMix64(static_cast<std::uint64_t>(index)));
  return unitInterval(splitMix64(item ^ splitMix64(draw + 0x632be59bd9b4e019ULL)));
}

/// The angle [rad] between a direction drawn from Fisher's distribution with concentration
/// `kappa` and its mean direction, from a uniform `u` in [0, 1): the exact inversion of its
/// cumulative distribution (Fisher 1953; Fisher, Lewis and Embleton 1987, eq. 3.39),
///   cos(theta) = 1 + ln(1 - u (1 - exp(-2 kappa))) / kappa,
/// written with log1p and expm1 so that it stays exact for large and small kappa. The azimuth
/// about the mean is uniform and drawn apart.
inline double fisherAngle(double kappa, double u) {
  const double c = 1.0 + std::log1p(u * std::expm1(-2.0 * kappa)) / kappa;
  return std::acos(std::clamp(c, -1.0, 1.0));
}

}  // namespace polydem

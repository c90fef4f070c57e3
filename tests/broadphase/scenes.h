// Sphere scenes for the broad-phase tests: owned storage plus a SphereSet view of it.
#pragma once

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include "polydem/broadphase/broad_phase.h"

namespace polydem::broadphase::testing {

struct Scene {
  std::vector<Vec3> centers;
  std::vector<double> radii;
  std::vector<Uid> uids;
  std::vector<std::uint8_t> active;

  void add(const Vec3& c, double r, std::uint8_t is_active = 1) {
    centers.push_back(c);
    radii.push_back(r);
    active.push_back(is_active);
    uids.push_back(0);  // numbered by finish()
  }
  /// Gives unique uids in an order unrelated to the index order.
  void finish(std::uint64_t seed) {
    uids.resize(centers.size());
    std::iota(uids.begin(), uids.end(), Uid{1000});
    std::shuffle(uids.begin(), uids.end(), std::mt19937_64(seed));
  }
  SphereSet view() const { return {centers, radii, uids, active}; }
};

struct RandomSceneSpec {
  int n = 500;
  double size_ratio = 1.0;      // largest / smallest radius, log-uniform in between
  double solid_fraction = 0.3;  // sum of sphere volumes / box volume (dense > 0.3, loose < 0.05)
  double inactive_fraction = 0.0;
  double scale = 1.0;          // smallest radius
  Vec3 offset = Vec3::Zero();  // added to every centre
  std::uint64_t seed = 1;
};

/// Spheres of log-uniform radii at uniformly random centres in a cube sized for the fraction.
inline Scene randomScene(const RandomSceneSpec& spec) {
  std::mt19937_64 rng(spec.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Scene s;
  double solid = 0.0;
  std::vector<double> radii(spec.n);
  for (double& r : radii) {
    r = spec.scale * std::pow(spec.size_ratio, unit(rng));
    solid += 4.0 / 3.0 * 3.14159265358979 * r * r * r;
  }
  const double side = std::cbrt(solid / spec.solid_fraction);
  for (int i = 0; i < spec.n; ++i) {
    const Vec3 c(unit(rng) * side, unit(rng) * side, unit(rng) * side);
    s.add(c + spec.offset, radii[i], unit(rng) < spec.inactive_fraction ? 0 : 1);
  }
  s.finish(spec.seed + 7);
  return s;
}

/// A cubic lattice of n^3 spheres of `radius`, `spacing` apart, starting at `offset`.
inline Scene latticeScene(int n, double spacing, double radius, const Vec3& offset) {
  Scene s;
  for (int z = 0; z < n; ++z) {
    for (int y = 0; y < n; ++y) {
      for (int x = 0; x < n; ++x) s.add(offset + spacing * Vec3(x, y, z), radius);
    }
  }
  s.finish(99);
  return s;
}

}  // namespace polydem::broadphase::testing

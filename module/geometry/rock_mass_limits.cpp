// The size of a rock mass estimated from its description before any cutting, and the limits it
// must keep (rock_mass.h): a spacing in mm for m is refused at once, with the numbers, instead
// of cutting for hours into more blocks than the memory holds.
//
// Blocks: the cells of an arrangement of planes in general position inside a convex region
// number 1 + P + L + V, with P the planes, L the lines where two of them meet and V the points
// where three meet, inside the region (Euler's relation for the arrangement: each plane, line
// and point adds one cell). For families of parallel planes i (normal n_i, spacing s_i) in a
// region of volume Vol: P_i = W_i / s_i (W_i the region's width along n_i), L_ij = A_ij
// |n_i x n_j| / (s_i s_j) (A_ij the region's cross-section across the lines, taken as Vol over
// its width along them) and V_ijk = Vol |det(n_i, n_j, n_k)| / (s_i s_j s_k). Three orthogonal
// sets of m planes across a box give (1 + m)^3, exactly. A single plane is a family of one.
#include <algorithm>
#include <cmath>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/geometry/rock_mass.h"

namespace polydem::geometry {

namespace {

// The region's width along the unit vector `u`.
double widthAlong(const std::vector<Vec3>& corners, const Vec3& u) {
  double lo = INFINITY, hi = -INFINITY;
  for (const Vec3& p : corners) {
    lo = std::min(lo, u.dot(p));
    hi = std::max(hi, u.dot(p));
  }
  return hi - lo;
}

struct Family {
  Vec3 normal;
  double spacing;
  double planes;
};

double expectedBlocks(const std::vector<Family>& f, const std::vector<Vec3>& corners,
                      double volume) {
  double blocks = 1.0;
  for (const Family& a : f) blocks += a.planes;
  for (std::size_t i = 0; i < f.size(); ++i) {
    for (std::size_t j = i + 1; j < f.size(); ++j) {
      const Vec3 line = f[i].normal.cross(f[j].normal);
      const double sine = line.norm();
      if (sine < 1e-12) continue;  // parallel families meet nowhere
      const double section = volume / widthAlong(corners, line / sine);
      blocks += section * sine / (f[i].spacing * f[j].spacing);
      for (std::size_t k = j + 1; k < f.size(); ++k) {
        blocks +=
            volume * std::abs(line.dot(f[k].normal)) / (f[i].spacing * f[j].spacing * f[k].spacing);
      }
    }
  }
  return blocks;
}

}  // namespace

RockMassEstimate estimateRockMass(const RockMassSpec& spec) {
  const std::vector<Vec3> corners = spec.region.corners();
  RockMassEstimate e;
  std::vector<Family> families;
  for (const SinglePlane& p : spec.planes) {
    const double width = widthAlong(corners, p.plane.normal);
    families.push_back({p.plane.normal, width, 1.0});
    e.families.push_back({p.name, width, 1.0});
  }
  for (const JointSet& set : spec.joint_sets) {
    const double planes = expectedPlaneCount(set, corners);  // checks the set's values
    families.push_back({normalFromDip(set.dip, set.dip_direction), set.spacing, planes});
    e.families.push_back({set.name, set.spacing, planes});
  }
  for (const Family& f : families) e.planes += f.planes;
  e.blocks = expectedBlocks(families, corners, spec.region.volume);
  return e;
}

void checkRockMassLimits(const RockMassSpec& spec) {
  const std::vector<Vec3> corners = spec.region.corners();
  for (const JointSet& set : spec.joint_sets) checkPlaneCount(set, corners);  // one set too many
  const RockMassEstimate e = estimateRockMass(spec);
  std::string sets;  // "'J1' 3750 planes at 0.008 m, 'fault' 1 plane"
  for (std::size_t i = 0; i < e.families.size(); ++i) {
    const RockMassEstimate::Family& f = e.families[i];
    const bool single = i < spec.planes.size();
    sets += cat(
        sets.empty() ? "" : ", ", "'", f.name, "' ",
        single ? std::string("1 plane") : cat(num(f.planes), " planes at ", num(f.spacing), " m"));
  }
  if (!(e.planes <= kMaxRockPlanes)) {
    throw GeometryError(cat("about ", num(e.planes), " planes would cross the region (", sets,
                            "), more than the limit of ", num(kMaxRockPlanes),
                            ": increase the joint sets' spacings"));
  }
  if (!(e.blocks <= spec.max_blocks)) {
    throw GeometryError(cat(
        "the planes would cut the region (", num(spec.region.volume), " m^3) into about ",
        num(e.blocks), " blocks (", sets, "), more than the limit of ", num(spec.max_blocks),
        ": increase the joint sets' spacings (the blocks grow as one over ",
        "their product) or cut a smaller region, or raise max_blocks if so ", "many are meant"));
  }
}

}  // namespace polydem::geometry

#include "polydem/geometry/joint_planes.h"

#include <algorithm>
#include <cmath>

#include "polydem/core/error.h"
#include "polydem/core/random.h"
#include "polydem/core/strings.h"

namespace polydem::geometry {

namespace {

// Draw streams of one plane (uniformAt's `draw`).
constexpr std::uint64_t kGap = 0, kTiltAngle = 1, kTiltAzimuth = 2;

// The gap between plane k and plane k + 1.
double gapAfter(const JointSet& set, std::int64_t k) {
  if (set.spacing_jitter == 0.0) return set.spacing;
  const double u = 2.0 * uniformAt(set.seed, k, kGap) - 1.0;
  return set.spacing * (1.0 + set.spacing_jitter * u);
}

// The normal of plane k: the set's normal turned by up to orientation_jitter in a random
// direction (angle ~ jitter sqrt(u): uniform over the small cap of directions), or by an angle
// drawn from Fisher's distribution (fisher_k).
Vec3 jitteredNormal(const JointSet& set, const Vec3& n0, std::int64_t k) {
  if (set.orientation_jitter == 0.0 && set.fisher_k == 0.0) return n0;
  const double u = uniformAt(set.seed, k, kTiltAngle);
  const double tilt = set.fisher_k > 0.0 ? fisherAngle(set.fisher_k, u)
                                         : degToRad(set.orientation_jitter) * std::sqrt(u);
  const double azimuth = 2.0 * kPi * uniformAt(set.seed, k, kTiltAzimuth);
  const Vec3 a = n0.unitOrthogonal();
  const Vec3 b = n0.cross(a);
  const Vec3 axis = std::cos(azimuth) * a + std::sin(azimuth) * b;
  const Vec3 n = std::cos(tilt) * n0 + std::sin(tilt) * axis;
  // Within 90 deg of the set's normal: "above" is the same side for every plane of the set. A
  // Fisher pole beyond 90 deg is the same plane as its opposite (joint poles are axial).
  return (tilt > 0.5 * kPi ? -n : n).normalized();
}

void checkSet(const JointSet& set) {
  const auto bad = [&set](const std::string& what) {
    throw GeometryError(cat("joint set '", set.name, "': ", what));
  };
  if (!(set.dip >= 0.0 && set.dip <= 90.0)) bad(cat("dip ", set.dip, " is not in [0, 90] deg"));
  if (!std::isfinite(set.dip_direction)) bad("dip direction is not finite");
  if (!(set.spacing > 0.0) || !std::isfinite(set.spacing)) bad("spacing must be > 0");
  if (!(set.spacing_jitter >= 0.0 && set.spacing_jitter < 1.0)) {
    bad("spacing jitter must be in [0, 1)");
  }
  if (!(set.orientation_jitter >= 0.0 && set.orientation_jitter < 90.0)) {
    bad("orientation jitter must be in [0, 90) deg");
  }
  if (!(set.fisher_k >= 0.0) || !std::isfinite(set.fisher_k)) {
    bad("Fisher's concentration K must be >= 0");
  }
  if (set.fisher_k > 0.0 && set.orientation_jitter > 0.0) {
    bad("orientation jitter and Fisher's concentration K are two scatters of the same normals: "
        "give one");
  }
}

}  // namespace

Vec3 normalFromDip(double dip_deg, double dip_direction_deg) {
  const double dip = degToRad(dip_deg), azimuth = degToRad(dip_direction_deg);
  return Vec3(std::sin(dip) * std::sin(azimuth), std::sin(dip) * std::cos(azimuth), std::cos(dip));
}

namespace {

// Where the hull of `points` lies along the set's normal, measured from plane 0 (m).
struct Extent {
  double lo = INFINITY, hi = -INFINITY;
  double diameter = 0.0;  // of the points' bounding box
};

Extent extentOf(const JointSet& set, const std::vector<Vec3>& points) {
  const Vec3 n0 = normalFromDip(set.dip, set.dip_direction);
  Extent e;
  Vec3 box_lo = Vec3::Constant(INFINITY), box_hi = Vec3::Constant(-INFINITY);
  for (const Vec3& p : points) {
    const double s = n0.dot(p - set.origin) - set.offset;
    e.lo = std::min(e.lo, s);
    e.hi = std::max(e.hi, s);
    box_lo = box_lo.cwiseMin(p);
    box_hi = box_hi.cwiseMax(p);
  }
  if (!points.empty()) e.diameter = (box_hi - box_lo).norm();
  return e;
}

// Refuses a set with more planes across the region than a rock mass may have, naming the
// spacing and the region's width that give them.
void checkCount(const JointSet& set, const Extent& e) {
  const double width = e.hi - e.lo;
  const double planes = width / set.spacing;
  if (!(planes <= kMaxRockPlanes)) {
    throw GeometryError(cat("joint set '", set.name, "': spacing ", num(set.spacing),
                            " m gives about ", num(planes), " planes across the region (",
                            num(width), " m wide along the set's normal), more than the limit of ",
                            num(kMaxRockPlanes), ": is the spacing in metres? Increase it"));
  }
}

}  // namespace

double expectedPlaneCount(const JointSet& set, const std::vector<Vec3>& points) {
  checkSet(set);
  if (points.empty()) return 0.0;
  const Extent e = extentOf(set, points);
  return (e.hi - e.lo) / set.spacing;
}

void checkPlaneCount(const JointSet& set, const std::vector<Vec3>& points) {
  checkSet(set);
  if (!points.empty()) checkCount(set, extentOf(set, points));
}

std::vector<JointPlane> jointSetPlanes(const JointSet& set, const std::vector<Vec3>& points) {
  checkSet(set);
  if (points.empty()) return {};
  const Vec3 n0 = normalFromDip(set.dip, set.dip_direction);
  Extent e = extentOf(set, points);
  checkCount(set, e);
  // Planes are counted from plane 0, gap by gap: the region must not lie too many gaps away.
  const double away = std::min(std::abs(e.lo), std::abs(e.hi)) * (e.lo * e.hi > 0.0);
  if (away > 1e7 * set.spacing) {
    throw GeometryError(cat("joint set '", set.name, "': the region lies ", num(away), " m (",
                            num(away / set.spacing), " spacings) from the set's plane 0 at origin",
                            " + offset along the normal, more than 1e7 spacings: planes are ",
                            "counted from plane 0, so put origin (or offset) near the region"));
  }
  // Tilted planes reach up to (diameter) sin(jitter) further: the range is widened by that; a
  // Fisher tilt has no bound below 90 deg, so by the whole diameter.
  const double reach =
      set.fisher_k > 0.0 ? e.diameter : e.diameter * std::sin(degToRad(set.orientation_jitter));
  const double lo = e.lo - reach, hi = e.hi + reach;
  // Jittered gaps average the spacing but may be as small as (1 - jitter) spacing: the count is
  // checked as the planes are made.
  const auto tooMany = [&](std::size_t n) {
    if (static_cast<double>(n) <= kMaxRockPlanes) return;
    throw GeometryError(cat("joint set '", set.name, "': more than ", num(kMaxRockPlanes),
                            " planes across the region (about ", num((hi - lo) / set.spacing),
                            " expected at spacing ", num(set.spacing), " m, spacing_jitter ",
                            num(set.spacing_jitter), "): increase the spacing"));
  };
  // Positions s_k of plane k along n0: s_0 = 0, s_{k+1} = s_k + gap(k).
  std::vector<std::pair<std::int64_t, double>> positions;
  double s = 0.0;
  for (std::int64_t k = 0; s <= hi; ++k) {
    if (s >= lo) positions.emplace_back(k, s);
    tooMany(positions.size());
    s += gapAfter(set, k);
  }
  s = 0.0;
  for (std::int64_t k = -1; s >= lo; --k) {
    s -= gapAfter(set, k);
    if (s >= lo && s <= hi) positions.emplace_back(k, s);
    tooMany(positions.size());
  }
  std::sort(positions.begin(), positions.end());
  std::vector<JointPlane> out;
  out.reserve(positions.size());
  for (const auto& [k, position] : positions) {
    const Vec3 anchor = set.origin + (set.offset + position) * n0;
    JointPlane p;
    p.index = k;
    p.plane.normal = jitteredNormal(set, n0, k);
    p.plane.offset = p.plane.normal.dot(anchor);
    out.push_back(p);
  }
  return out;
}

}  // namespace polydem::geometry

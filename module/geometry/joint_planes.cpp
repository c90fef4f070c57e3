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
// direction (angle ~ jitter sqrt(u): uniform over the small cap of directions).
Vec3 jitteredNormal(const JointSet& set, const Vec3& n0, std::int64_t k) {
  if (set.orientation_jitter == 0.0) return n0;
  const double tilt =
      degToRad(set.orientation_jitter) * std::sqrt(uniformAt(set.seed, k, kTiltAngle));
  const double azimuth = 2.0 * kPi * uniformAt(set.seed, k, kTiltAzimuth);
  const Vec3 a = n0.unitOrthogonal();
  const Vec3 b = n0.cross(a);
  const Vec3 axis = std::cos(azimuth) * a + std::sin(azimuth) * b;
  const Vec3 n = std::cos(tilt) * n0 + std::sin(tilt) * axis;
  // Within 90 deg of the set's normal: "above" is the same side for every plane of the set.
  return n.normalized();
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
}

}  // namespace

Vec3 normalFromDip(double dip_deg, double dip_direction_deg) {
  const double dip = degToRad(dip_deg), azimuth = degToRad(dip_direction_deg);
  return Vec3(std::sin(dip) * std::sin(azimuth), std::sin(dip) * std::cos(azimuth), std::cos(dip));
}

std::vector<JointPlane> jointSetPlanes(const JointSet& set, const std::vector<Vec3>& points) {
  checkSet(set);
  const Vec3 n0 = normalFromDip(set.dip, set.dip_direction);
  // Extent of the region along the set's normal, from plane 0; tilted planes reach up to
  // (diameter) sin(jitter) further, so the range is widened by that.
  double lo = INFINITY, hi = -INFINITY;
  Vec3 box_lo = Vec3::Constant(INFINITY), box_hi = Vec3::Constant(-INFINITY);
  for (const Vec3& p : points) {
    const double s = n0.dot(p - set.origin) - set.offset;
    lo = std::min(lo, s);
    hi = std::max(hi, s);
    box_lo = box_lo.cwiseMin(p);
    box_hi = box_hi.cwiseMax(p);
  }
  if (points.empty()) return {};
  if (std::max(std::abs(lo), std::abs(hi)) > 1e7 * set.spacing) {
    throw GeometryError(cat("joint set '", set.name, "': the region lies more than 1e7 spacings ",
                            "from the set's plane 0 (check origin and offset)"));
  }
  const double reach = (box_hi - box_lo).norm() * std::sin(degToRad(set.orientation_jitter));
  lo -= reach;
  hi += reach;
  // Gaps are at least (1 - jitter) spacing: this bounds the number of planes.
  const double planes = (hi - lo) / (set.spacing * (1.0 - set.spacing_jitter));
  if (planes > 1e6) {
    throw GeometryError(cat("joint set '", set.name, "': spacing ", set.spacing, " m gives about ",
                            num(planes), " planes across the region"));
  }
  // Positions s_k of plane k along n0: s_0 = 0, s_{k+1} = s_k + gap(k).
  std::vector<std::pair<std::int64_t, double>> positions;
  double s = 0.0;
  for (std::int64_t k = 0; s <= hi; ++k) {
    if (s >= lo) positions.emplace_back(k, s);
    s += gapAfter(set, k);
  }
  s = 0.0;
  for (std::int64_t k = -1; s >= lo; --k) {
    s -= gapAfter(set, k);
    if (s >= lo && s <= hi) positions.emplace_back(k, s);
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

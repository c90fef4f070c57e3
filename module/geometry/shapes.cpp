#include "polydem/geometry/shapes.h"

#include <cmath>
#include <random>
#include <string>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"

namespace polydem::geometry::shapes {

namespace {

const double kPhi = 0.5 * (1.0 + std::sqrt(5.0));

void requirePositive(double value, const char* what) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    throw GeometryError(std::string("shape parameter '") + what + "' must be finite and > 0, got " +
                        cat(value));
  }
}

/// Uniform double in [0, 1) from the top 53 bits: the same on every platform, unlike
/// std::uniform_real_distribution whose algorithm the standard leaves open.
double uniform01(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

std::vector<Vec3> scaledBy(std::vector<Vec3> points, double factor) {
  for (Vec3& p : points) p *= factor;
  return points;
}

/// All sign combinations of (a, b, c) over the coordinates that are not zero.
void addSigned(std::vector<Vec3>& out, double a, double b, double c) {
  for (double sa : {1.0, -1.0}) {
    for (double sb : {1.0, -1.0}) {
      for (double sc : {1.0, -1.0}) {
        const Vec3 p(sa * a, sb * b, sc * c);
        if ((a == 0.0 && sa < 0) || (b == 0.0 && sb < 0) || (c == 0.0 && sc < 0)) continue;
        out.push_back(p);
      }
    }
  }
}

/// addSigned for the three cyclic permutations of (a, b, c).
void addCyclic(std::vector<Vec3>& out, double a, double b, double c) {
  addSigned(out, a, b, c);
  addSigned(out, b, c, a);
  addSigned(out, c, a, b);
}

}  // namespace

std::vector<Vec3> box(const Vec3& lo, const Vec3& hi) {
  for (int k = 0; k < 3; ++k) requirePositive(hi[k] - lo[k], "box hi - lo");
  std::vector<Vec3> out;
  for (int i = 0; i < 8; ++i) {
    out.emplace_back((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(),
                     (i & 4) ? hi.z() : lo.z());
  }
  return out;
}

std::vector<Vec3> boxAround(const Vec3& centre, const Vec3& half_extents) {
  for (int k = 0; k < 3; ++k) requirePositive(half_extents[k], "box half-extent");
  return box(centre - half_extents, centre + half_extents);
}

std::vector<Vec3> prism(const std::vector<Vec3>& base, const Vec3& extrusion) {
  if (base.size() < 3) {
    throw GeometryError("prism: the base polygon needs at least 3 corners, got " +
                        std::to_string(base.size()));
  }
  requirePositive(extrusion.norm(), "prism extrusion length");
  std::vector<Vec3> out = base;
  for (const Vec3& p : base) out.push_back(p + extrusion);
  return out;
}

std::vector<Vec3> ridgePrism(const Vec3& ridge_a, const Vec3& ridge_b, double base_half_width,
                             double height) {
  requirePositive(base_half_width, "ridge prism base half-width");
  requirePositive(height, "ridge prism height");
  const Vec3 along = ridge_b - ridge_a;
  requirePositive(along.norm(), "ridge length");
  if (ridge_a.z() != ridge_b.z()) {
    throw GeometryError("ridge prism: the ridge must be horizontal (ridge ends at z = " +
                        cat(ridge_a.z(), " and ", ridge_b.z(), ")"));
  }
  const Vec3 side = Vec3(-along.y(), along.x(), 0.0).normalized() * base_half_width;
  const Vec3 down(0.0, 0.0, height);
  return {ridge_a,
          ridge_b,
          ridge_a - down + side,
          ridge_a - down - side,
          ridge_b - down + side,
          ridge_b - down - side};
}

std::vector<Vec3> squarePyramid(const Vec3& apex, double base_side, double height, Apex direction,
                                double turn) {
  requirePositive(base_side, "pyramid base side");
  requirePositive(height, "pyramid height");
  const double z = apex.z() + (direction == Apex::kUp ? -height : height);
  const double h = 0.5 * base_side;
  const double c = std::cos(turn), s = std::sin(turn);
  std::vector<Vec3> out{apex};
  for (const auto& [x, y] : {std::pair{h, h}, {-h, h}, {-h, -h}, {h, -h}}) {
    out.emplace_back(apex.x() + c * x - s * y, apex.y() + s * x + c * y, z);
  }
  return out;
}

double platonicCircumradiusPerEdge(Platonic solid) {
  switch (solid) {
    case Platonic::kTetrahedron:
      return std::sqrt(6.0) / 4.0;
    case Platonic::kCube:
      return std::sqrt(3.0) / 2.0;
    case Platonic::kOctahedron:
      return std::sqrt(2.0) / 2.0;
    case Platonic::kDodecahedron:
      return std::sqrt(3.0) * kPhi / 2.0;
    case Platonic::kIcosahedron:
      return std::sqrt(kPhi * kPhi + 1.0) / 2.0;
  }
  throw GeometryError("unknown Platonic solid");
}

std::vector<Vec3> platonic(Platonic solid, double edge) {
  requirePositive(edge, "edge length");
  std::vector<Vec3> unit;  // a solid of known edge length, then scaled
  double unit_edge = 2.0;
  switch (solid) {
    case Platonic::kTetrahedron:
      unit = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
      unit_edge = 2.0 * std::sqrt(2.0);
      break;
    case Platonic::kCube:
      addSigned(unit, 1, 1, 1);
      break;
    case Platonic::kOctahedron:
      addCyclic(unit, 1, 0, 0);
      unit_edge = std::sqrt(2.0);
      break;
    case Platonic::kDodecahedron:
      addSigned(unit, 1, 1, 1);
      addCyclic(unit, 0, 1 / kPhi, kPhi);
      unit_edge = 2.0 / kPhi;
      break;
    case Platonic::kIcosahedron:
      addCyclic(unit, 0, 1, kPhi);
      break;
  }
  return scaledBy(std::move(unit), edge / unit_edge);
}

std::vector<Vec3> platonicWithCircumradius(Platonic solid, double circumradius) {
  requirePositive(circumradius, "circumradius");
  return platonic(solid, circumradius / platonicCircumradiusPerEdge(solid));
}

std::vector<Vec3> hexagonalPrism(double side, double length) {
  requirePositive(side, "hexagon side");
  requirePositive(length, "prism length");
  std::vector<Vec3> base;
  const double half_height = 0.5 * std::sqrt(3.0) * side;
  for (const auto& [x, y] : {std::pair{side, 0.0},
                             {0.5 * side, half_height},
                             {-0.5 * side, half_height},
                             {-side, 0.0},
                             {-0.5 * side, -half_height},
                             {0.5 * side, -half_height}}) {
    base.emplace_back(x, y, -0.5 * length);
  }
  return prism(base, Vec3(0.0, 0.0, length));
}

std::vector<Vec3> randomConvex(int n, std::uint64_t seed, const Vec3& semi_axes,
                               double perturbation) {
  if (n < 4 || n > kMaxRandomPoints) {
    throw GeometryError(cat("randomConvex needs 4 <= n <= ", kMaxRandomPoints, " points, got ", n));
  }
  for (int k = 0; k < 3; ++k) requirePositive(semi_axes[k], "ellipsoid semi-axis");
  if (!(perturbation >= 0.0 && perturbation < 1.0)) {
    throw GeometryError("randomConvex: perturbation must be in [0, 1), got " + cat(perturbation));
  }
  std::mt19937_64 rng(seed);
  Vec3 axes = semi_axes;
  for (int k = 0; k < 3; ++k) axes[k] *= 1.0 + perturbation * (2.0 * uniform01(rng) - 1.0);
  std::vector<Vec3> out;
  out.reserve(n);
  for (int i = 0; i < n; ++i) {
    // Uniform on the unit sphere (Archimedes: z uniform in [-1, 1]), then stretched.
    const double z = 2.0 * uniform01(rng) - 1.0;
    const double phi = 2.0 * kPi * uniform01(rng);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    out.emplace_back(axes.x() * r * std::cos(phi), axes.y() * r * std::sin(phi), axes.z() * z);
  }
  return out;
}

}  // namespace polydem::geometry::shapes

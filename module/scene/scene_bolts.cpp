// [[bolt]]: rock bolts and cables (docs/scene-format.md "Rock bolts"): a straight segment from a
// point along a direction over a length, with the stiffness and yield force of its axial and shear
// response. The blocks it crosses are found when the simulation is built (sim/bolt_geometry.h).
#include <cmath>
#include <numbers>

#include "polydem/core/strings.h"
#include "polydem/scene/scene_sections.h"

namespace polydem::scene::detail {

namespace {

// The bolt's direction: a vector, or trend (degrees clockwise from north = +y) and plunge
// (degrees below the horizontal), as joint orientations are given by dip direction and dip.
Vec3 readDirection(const Section& s) {
  const bool vector = s.has("direction");
  const bool angles = s.has("trend") || s.has("plunge");
  if (vector && angles) s.fail("direction", "give direction or trend and plunge, not both");
  if (vector) {
    const Vec3 d = *s.vec3("direction", Quantity::kDimensionless);
    if (!(d.norm() > 0.0) || !d.allFinite()) s.fail("direction", "must be a non-zero vector");
    return d.normalized();
  }
  if (!angles) s.failHere("give direction = [x, y, z], or trend and plunge (degrees)");
  if (!s.has("trend")) s.missing("trend");
  if (!s.has("plunge")) s.missing("plunge");
  const double trend = s.bounded("trend", Quantity::kAngle, 0.0, 0.0, 360.0, true);
  const double plunge = s.bounded("plunge", Quantity::kAngle, 0.0, -90.0, 90.0, true);
  const double t = trend * std::numbers::pi / 180.0, p = plunge * std::numbers::pi / 180.0;
  return Vec3(std::sin(t) * std::cos(p), std::cos(t) * std::cos(p), -std::sin(p));
}

setup::BoltSpec readBolt(const Section& s) {
  s.allowOnly({"name", "start", "direction", "trend", "plunge", "length", "axial_stiffness",
               "axial_yield", "shear_stiffness", "shear_yield", "pretension",
               "ultimate_elongation"});
  setup::BoltSpec b;
  b.name = s.requiredString("name");
  b.line = s.line();
  if (!s.has("start")) s.missing("start");
  b.start = *s.vec3("start", Quantity::kLength);
  b.direction = readDirection(s);
  b.length = s.requiredNumber("length", Quantity::kLength, Range::kPositive);
  b.axial_stiffness = s.requiredNumber("axial_stiffness", Quantity::kStiffness, Range::kPositive);
  b.axial_yield = s.requiredNumber("axial_yield", Quantity::kForce, Range::kPositive);
  b.shear_stiffness =
      s.requiredNumber("shear_stiffness", Quantity::kStiffness, Range::kNonNegative);
  b.shear_yield = s.requiredNumber("shear_yield", Quantity::kForce, Range::kNonNegative);
  b.pretension = s.number("pretension", Quantity::kForce, 0.0, Range::kNonNegative);
  if (b.pretension > b.axial_yield) {
    s.fail("pretension", cat("exceeds axial_yield (", b.pretension, " N > ", b.axial_yield, " N)"));
  }
  b.ultimate_elongation = s.number("ultimate_elongation", Quantity::kLength, Range::kPositive);
  return b;
}

}  // namespace

void readBolts(const Context& ctx, const toml::table& root, setup::Setup& scene) {
  for (const Section& s : entries(ctx, root, "bolt", "name")) {
    setup::BoltSpec b = readBolt(s);
    if (indexByName(scene.bolts, b.name) >= 0) {
      s.fail("name", "another [[bolt]] is named '" + b.name + "'");
    }
    scene.bolts.push_back(std::move(b));
  }
}

}  // namespace polydem::scene::detail

// [[joint]]: the stiffness and strength of a rock joint, referenced by name from the joint sets
// and planes of a [[rock_mass]] (docs/scene-format.md, "Joints"). Stresses in Pa, stiffness per
// area in Pa/m, as 3DEC, SWedge and rock mechanics texts give them.
#include <map>

#include "polydem/core/strings.h"
#include "polydem/scene/scene_sections.h"

namespace polydem::io::detail {

void readJoints(const Context& ctx, const toml::table& root, Scene& scene) {
  std::map<std::string, int> lines;
  for (const Section& s : entries(ctx, root, "joint", "name")) {
    s.allowOnly({"name", "law", "jkn", "jks", "friction_angle", "cohesion", "tensile_strength"});
    JointSpec j;
    j.name = s.requiredString("name");
    if (const auto it = lines.find(j.name); it != lines.end()) {
      s.fail("name", cat("joint '", j.name, "' is already defined at line ", it->second));
    }
    lines[j.name] = s.line();
    j.line = s.line();
    j.law = s.choice("law", {"coulomb"}, "coulomb");
    j.jkn = s.requiredNumber("jkn", Quantity::kJointStiffness, Range::kPositive);
    j.jks = s.requiredNumber("jks", Quantity::kJointStiffness, Range::kPositive);
    if (!s.has("friction_angle")) s.missing("friction_angle");
    j.friction_angle = s.bounded("friction_angle", Quantity::kAngle, 0.0, 0.0, 90.0, false);
    j.cohesion = s.number("cohesion", Quantity::kPressure, 0.0, Range::kNonNegative);
    j.tensile_strength =
        s.number("tensile_strength", Quantity::kPressure, 0.0, Range::kNonNegative);
    scene.joints.push_back(j);
  }
}

int jointReference(const Section& s, std::string_view key, const Scene& scene) {
  const auto name = s.string(key);
  if (!name) return -1;
  const int index = indexByName(scene.joints, *name);
  if (index < 0) s.fail(key, cat("no [[joint]] is named '", *name, "'"));
  return index;
}

}  // namespace polydem::io::detail

// [[joint]]: a rock joint's law and its parameters, referenced by name from the joint sets and
// planes of a [[rock_mass]] (docs/scene-format.md, "Joints"). The keys, units, ranges and defaults
// are each law's own declaration (dynamics/joint_law.h): stresses in Pa, stiffness per area in
// Pa/m, angles in degrees, lengths in m, as 3DEC, SWedge and rock mechanics texts give them.
#include <map>

#include "polydem/core/strings.h"
#include "polydem/dynamics/joint_law.h"
#include "polydem/scene/scene_sections.h"

namespace polydem::scene::detail {

namespace {

Quantity quantityOf(dynamics::ParameterUnit unit) {
  switch (unit) {
    case dynamics::ParameterUnit::kJointStiffness:
      return Quantity::kJointStiffness;
    case dynamics::ParameterUnit::kPressure:
      return Quantity::kPressure;
    case dynamics::ParameterUnit::kAngle:
      return Quantity::kAngle;
    case dynamics::ParameterUnit::kLength:
      return Quantity::kLength;
    case dynamics::ParameterUnit::kDimensionless:
    case dynamics::ParameterUnit::kFlag:
      break;
  }
  return Quantity::kDimensionless;
}

// "[0, 90)", "> 0": the range of a parameter for messages.
std::string rangeText(const dynamics::LawParameter& p) {
  if (p.max >= 1e300) return cat(p.min_inclusive ? ">= " : "> ", p.min);
  return cat(p.min_inclusive ? "[" : "(", p.min, ", ", p.max, p.max_inclusive ? "]" : ")");
}

// The value of parameter `p` of the joint in `s`: given, or its default.
double readParameter(const Section& s, const dynamics::LawParameter& p,
                     const dynamics::JointLawInfo& law, const std::vector<double>& read) {
  if (p.unit == dynamics::ParameterUnit::kFlag) {
    if (!s.has(p.name)) return p.fallback;
    const auto flag = s.boolean(p.name);
    if (!flag) s.fail(p.name, "expected true or false");
    return *flag ? 1.0 : 0.0;
  }
  if (!s.has(p.name)) {
    if (p.required) s.missing(p.name);
    if (p.default_from) {
      return read[static_cast<std::size_t>(dynamics::parameterIndex(law, p.default_from))];
    }
    return p.fallback;
  }
  const double v = *s.number(p.name, quantityOf(p.unit));
  const bool above = p.min_inclusive ? v >= p.min : v > p.min;
  const bool below = p.max_inclusive ? v <= p.max : v < p.max;
  if (!(above && below)) {
    s.fail(p.name, cat("must be ", rangeText(p), " for law '", law.name, "', got ", v));
  }
  return v;
}

}  // namespace

void readJoints(const Context& ctx, const toml::table& root, setup::Setup& scene) {
  std::vector<std::string> law_names;
  for (const auto& law : dynamics::jointLaws()) law_names.emplace_back(law.name);
  std::map<std::string, int> lines;
  for (const Section& s : entries(ctx, root, "joint", "name")) {
    const std::string law_name = s.choice("law", law_names, "coulomb");
    const dynamics::JointLawInfo& law = *dynamics::findJointLaw(law_name);
    std::vector<std::string_view> known{"name", "law"};
    for (const auto& p : law.parameters) known.emplace_back(p.name);
    s.allowOnly(known);
    setup::JointSpec j;
    j.name = s.requiredString("name");
    if (const auto it = lines.find(j.name); it != lines.end()) {
      s.fail("name", cat("joint '", j.name, "' is already defined at line ", it->second));
    }
    lines[j.name] = s.line();
    j.line = s.line();
    j.law.law = law.id;
    // In declared order: a default taken from another parameter names one declared before it.
    for (const auto& p : law.parameters) {
      j.law.values.push_back(readParameter(s, p, law, j.law.values));
    }
    scene.joints.push_back(j);
  }
}

int jointReference(const Section& s, std::string_view key, const setup::Setup& scene) {
  const auto name = s.string(key);
  if (!name) return -1;
  const int index = indexByName(scene.joints, *name);
  if (index < 0) s.fail(key, cat("no [[joint]] is named '", *name, "'"));
  return index;
}

}  // namespace polydem::scene::detail

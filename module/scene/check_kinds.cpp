#include "polydem/scene/check_kinds.h"

#include <string>

#include "polydem/setup/setup.h"

namespace polydem::scene {

namespace {

using T = CheckParamType;
constexpr double kInf = std::numeric_limits<double>::infinity();

CheckParam particles(std::string_view help = "labels of the particles, comma-separated") {
  return {"particle", T::kParticles, true, {}, -kInf, kInf, false, false, {}, help};
}
CheckParam particle() {
  return {"particle", T::kParticle, true, {}, -kInf, kInf, false, false, {}, "its label"};
}
CheckParam direction(std::string_view name, bool required, std::string_view help) {
  return {name, T::kDirection, required, {}, -kInf, kInf, false, false, {}, help};
}
CheckParam number(std::string_view name, bool required, Quantity q, double lo, double hi,
                  bool lo_open, bool hi_open, std::string_view help) {
  return {name, T::kNumber, required, q, lo, hi, lo_open, hi_open, {}, help};
}
CheckParam word(std::string_view name, std::vector<std::string_view> words, std::string_view help) {
  return {name, T::kWord, false, {}, -kInf, kInf, false, false, std::move(words), help};
}

CheckParam labelPrefix(bool required) {
  return {"label_prefix",
          T::kText,
          required,
          {},
          -kInf,
          kInf,
          false,
          false,
          {},
          "the blocks' label prefix (prefix_0, prefix_1, ...; default: every free block)"};
}
CheckParam measuredNumber(std::string_view name, std::string_view help) {
  CheckParam p = number(name, false, Quantity::kDimensionless, 0.0, kInf, false, false, help);
  p.measured = true;
  return p;
}

// The incline and the gravity of the curve checks (Zhao eqs. 41-42 and 45).
CheckParam theta(bool zero_allowed) {
  return number("theta", true, Quantity::kAngle, 0.0, 90.0, !zero_allowed, false,
                "inclination of the plane (of the intersection line for a wedge), degrees");
}
CheckParam gravity() {
  return number("g", false, Quantity::kAcceleration, 0.0, kInf, true, false,
                "gravity of the analytical curve (default: |[simulation] gravity|)");
}

std::vector<CheckKind> makeKinds() {
  using Q = Quantity;
  return {
      {"displacement",
       Q::kLength,
       "largest (or final) displacement of the particles, m",
       {particles(), direction("direction", false, "only the component along it (default: all)"),
        word("at", {"max", "end"}, "\"max\" over the run (default) or at the \"end\"")}},
      {"rotation",
       Q::kPhase,
       "largest rotation angle of the particles, rad",
       {particles(), direction("axis", false, "only the rotation about it (default: any)")}},
      {"lateral_drift",
       Q::kDimensionless,
       "largest drift across `lateral` divided by the final travel along `direction` (a ratio)",
       {particle(), direction("direction", true, "of travel"),
        direction("lateral", true, "across the travel")}},
      {"sliding_block",
       Q::kDimensionless,
       "largest |numerical - analytical| over the largest analytical value (Zhao eqs. 41-42)",
       {particle(), theta(true),
        number("mu", true, Q::kDimensionless, 0.0, kInf, false, false, "friction coefficient"),
        number("u0", true, Q::kVelocity, 0.0, kInf, false, false, "launch speed up the slope, m/s"),
        gravity(), direction("direction", true, "up the slope"),
        word("quantity", {"displacement", "velocity"},
             "compare the \"displacement\" (default) or the \"velocity\"")}},
      {"wedge_slide",
       Q::kDimensionless,
       "largest |numerical - analytical| travel over the final analytical travel (Zhao eq. 45)",
       {particle(), theta(false), gravity(),
        direction("direction", true, "down the intersection line")}},
      {"kinetic_energy_ratio",
       Q::kDimensionless,
       "kinetic energy after the first contact ends over that just before it began",
       {particle()}},
      {"separation_time",
       Q::kTime,
       "first time the particle, once in contact, has none, s",
       {particle()}},
      {"equilibrium_steps", Q::kDimensionless, "steps of the initial-equilibrium stage", {}},
      {"mean_speed", Q::kVelocity, "mean speed of the free particles at the end, m/s", {}},
      {"max_speed", Q::kVelocity, "largest speed of the free particles at the end, m/s", {}},
      {"contact_count", Q::kDimensionless, "touching pairs at the end, each counted once", {}},
      {"max_contact_force",
       Q::kDimensionless,
       "largest contact force between free particles across `axis`, over their mean weight",
       {direction("axis", false, "the force component along it is left out (default: gravity)")}},
      // The rock-slope kinds (run/motion_checks.h).
      {"free_motion",
       Q::kLength,
       "a statistic of the free blocks' motion, in its quantity's unit (m, m/s or rad/s); "
       "with at = \"first_below\" the time it first falls below `limit`, s",
       {{"quantity",
         T::kWord,
         true,
         {},
         -kInf,
         kInf,
         false,
         false,
         {"mean_displacement", "max_displacement", "mean_speed", "max_speed", "max_angular_speed",
          "front_advance"},
         "what is measured"},
        labelPrefix(false),
        direction("direction", false, "of the front (front_advance needs it)"),
        word("at", {"end", "max", "first_below"},
             "its value at the \"end\" (default), the \"max\" after `after`, or the "
             "\"first_below\" time"),
        number("after", false, Q::kTime, 0.0, kInf, false, false,
               "start of the window of max / first_below, s (default 0)"),
        number("every", false, Q::kDimensionless, 1.0, kInf, false, false,
               "steps between samples (default 1)"),
        measuredNumber("limit", "first_below: the value to fall below, in the quantity's unit")}},
      {"tilt_failure",
       Q::kAngle,
       "the platform's tilt when a block first moves `threshold` against it, deg; with measure = "
       "\"rotation\", the slope's turn when a block first moves `reach`: the mass-weighted "
       "median turn against the platform of the blocks that have moved reach / 10",
       {labelPrefix(true),
        {"platform", T::kParticle, true, {}, -kInf, kInf, false, false, {}, "the tilting body"},
        word("measure", {"angle", "rotation"}, "\"angle\" (the tilt; default) or \"rotation\""),
        number("threshold", false, Q::kLength, 0.0, kInf, true, false,
               "tilt: displacement against the platform that counts as failure, m"),
        number("reach", false, Q::kLength, 0.0, kInf, true, false,
               "rotation: displacement of the first block at which the slope's turn is read, m")}},
      {"pair_separation",
       Q::kTime,
       "first time two particles that pressed on each other with at least `min_force` stop, s",
       {particles("the two labels, \"a, b\""),
        number("min_force", false, Q::kForce, 0.0, kInf, false, false,
               "the force that counts as pressing, N (default 0)")}},
  };
}

}  // namespace

const std::vector<CheckKind>& checkKinds() {
  static const std::vector<CheckKind> kinds = makeKinds();
  return kinds;
}

const CheckKind* findCheckKind(std::string_view name) {
  for (const auto& k : checkKinds()) {
    if (k.name == name) return &k;
  }
  return nullptr;
}

const CheckParam* findCheckParam(const CheckKind& kind, std::string_view name) {
  for (const auto& p : kind.params) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

Quantity measuredQuantity(const CheckKind& kind, const setup::CheckSpec& spec) {
  if (kind.name != "free_motion") return kind.value;
  const auto it = spec.strings.find("quantity");
  const std::string q = it == spec.strings.end() ? std::string() : it->second;
  if (q == "mean_speed" || q == "max_speed") return Quantity::kVelocity;
  if (q == "max_angular_speed") return Quantity::kAngularVelocity;
  return Quantity::kLength;  // displacements and the front's advance
}

Quantity valueQuantity(const CheckKind& kind, const setup::CheckSpec& spec) {
  const auto at = spec.strings.find("at");
  if (kind.name == "free_motion" && at != spec.strings.end() && at->second == "first_below") {
    return Quantity::kTime;
  }
  return measuredQuantity(kind, spec);
}

std::string checkKindNames() {
  std::string out;
  for (const auto& k : checkKinds()) out += (out.empty() ? "" : ", ") + std::string(k.name);
  return out;
}

}  // namespace polydem::scene

// [[check]]: the expected results of a scene. Every kind declares its parameters, their types
// and ranges (check_kinds.h); a key the kind does not declare, a missing required one, a
// value out of range or a label no particle has is an error at its line.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "polydem/core/strings.h"
#include "polydem/scene/check_kinds.h"
#include "polydem/scene/scene_sections.h"

namespace polydem::scene::detail {

namespace {

const std::vector<std::string_view> kFixedKeys = {"name",      "kind",    "expected",
                                                  "tolerance", "compare", "reference"};

// A bound or a value in messages, to 10 significant digits.
std::string showBound(double v) {
  std::ostringstream out;
  out.precision(10);
  out << v;
  return out.str();
}

/// "[0, 90)", "> 0"...: a parameter's range, for messages.
std::string rangeText(const CheckParam& p) {
  const bool lo = std::isfinite(p.lo), hi = std::isfinite(p.hi);
  if (lo && hi) {
    return cat(p.lo_open ? "(" : "[", showBound(p.lo), ", ", showBound(p.hi),
               p.hi_open ? ")" : "]");
  }
  if (lo) return cat(p.lo_open ? "> " : ">= ", showBound(p.lo));
  if (hi) return cat(p.hi_open ? "< " : "<= ", showBound(p.hi));
  return "any finite number";
}

bool inRange(const CheckParam& p, double v) {
  const bool above = p.lo_open ? v > p.lo : v >= p.lo;
  const bool below = p.hi_open ? v < p.hi : v <= p.hi;
  return above && below;
}

/// The labels of a "a, b, c" list, each of which some particle must carry.
std::vector<std::string> labels(const Section& s, const CheckParam& p, const setup::Setup& scene) {
  const std::string list = s.requiredString(p.name);
  std::vector<std::string> out;
  std::stringstream in(list);
  std::string label;
  while (std::getline(in, label, ',')) {
    label.erase(0, label.find_first_not_of(" \t"));
    label.erase(label.find_last_not_of(" \t") + 1);
    if (label.empty()) s.fail(p.name, "'" + list + "' has an empty label");
    const bool known = std::any_of(scene.particles.begin(), scene.particles.end(),
                                   [&](const setup::ParticleSpec& q) { return q.label == label; });
    if (!known) s.fail(p.name, "no particle is labelled '" + label + "'");
    out.push_back(label);
  }
  if (p.type == CheckParamType::kParticle && out.size() != 1) {
    s.fail(p.name, "takes one particle label, got '" + list + "'");
  }
  return out;
}

/// A direction, normalised without overflow or underflow (scaled by its largest component).
std::vector<double> direction(const Section& s, const CheckParam& p) {
  const Vec3 v = *s.vec3(p.name, Quantity::kDimensionless);
  const double scale = v.cwiseAbs().maxCoeff();
  if (!(scale > 0.0)) s.fail(p.name, "must not be zero");
  const Vec3 unit = (v / scale).normalized();
  return {unit.x(), unit.y(), unit.z()};
}

void readParameter(const Section& s, const CheckParam& p, Quantity measured,
                   const setup::Setup& scene, setup::CheckSpec& c) {
  const std::string key(p.name);
  switch (p.type) {
    case CheckParamType::kNumber: {
      const double v = *s.number(p.name, p.measured ? measured : p.quantity);
      if (!inRange(p, v)) s.fail(p.name, cat("must be ", rangeText(p), ", got ", showBound(v)));
      c.numbers[key] = {v};
      break;
    }
    case CheckParamType::kDirection:
      c.numbers[key] = direction(s, p);
      break;
    case CheckParamType::kParticles:
    case CheckParamType::kParticle:
      c.strings[key] = join(labels(s, p, scene), ",");
      break;
    case CheckParamType::kText: {
      const std::string text = s.requiredString(p.name);
      if (text.empty()) s.fail(p.name, "must not be empty");
      c.strings[key] = text;
      break;
    }
    case CheckParamType::kWord: {
      std::vector<std::string> words(p.words.begin(), p.words.end());
      c.strings[key] = s.choice(p.name, words, "");
      break;
    }
  }
}

}  // namespace

void readChecks(const Context& ctx, const toml::table& root, setup::Setup& scene) {
  for (const Section& s : entries(ctx, root, "check", "name")) {
    setup::CheckSpec c;
    c.name = s.requiredString("name");
    for (const setup::CheckSpec& other : scene.checks) {
      if (other.name == c.name) {
        s.fail("name",
               "check '" + c.name + "' is already defined at line " + std::to_string(other.line));
      }
    }
    c.kind = s.requiredString("kind");
    const CheckKind* kind = findCheckKind(c.kind);
    if (!kind) s.fail("kind", "'" + c.kind + "' is not a check kind; known: " + checkKindNames());
    std::vector<std::string_view> known = kFixedKeys;
    for (const auto& p : kind->params) known.push_back(p.name);
    s.allowOnly(known);
    c.compare = s.choice("compare", {"abs", "rel", "max", "min", "report"}, c.compare);
    c.reference = s.string("reference").value_or("");
    // Words and labels first: free_motion's `quantity` and `at` decide the unit of its numbers.
    for (const bool numbers : {false, true}) {
      for (const auto& p : kind->params) {
        if ((p.type == CheckParamType::kNumber) != numbers) continue;
        if (s.has(p.name)) {
          readParameter(s, p, measuredQuantity(*kind, c), scene, c);
        } else if (p.required) {
          s.missing(p.name);
        }
      }
    }
    const Quantity value = valueQuantity(*kind, c);
    if (s.has("expected")) {
      c.expected = *s.number("expected", value);
    } else if (c.compare != "report") {
      s.missing("expected");
    }
    c.tolerance = s.number("tolerance", value, 0.0, Range::kNonNegative);
    c.line = s.line();
    scene.checks.push_back(std::move(c));
  }
}

}  // namespace polydem::scene::detail

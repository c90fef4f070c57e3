// The parameters of a rock-slope check kind (free_motion, tilt_failure, pair_separation), each
// read with its type and lower bound checked again: these kinds also serve C++ programs that put
// a CheckSpec into their setup without the scene reader. A key the kind does not know is an error.
#pragma once

#include <optional>
#include <set>
#include <string>
#include <vector>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/core/types.h"
#include "polydem/run/free_motion.h"
#include "polydem/setup/setup.h"

namespace polydem::run {

class Keys {
 public:
  Keys(const setup::Setup& scene, const setup::CheckSpec& spec, std::set<std::string> known)
      : scene_(scene), spec_(spec) {
    for (const auto& [key, value] : spec.numbers) {
      if (!known.count(key)) fail(cat("unknown parameter '", key, "'"));
    }
    for (const auto& [key, value] : spec.strings) {
      if (!known.count(key)) fail(cat("unknown parameter '", key, "'"));
    }
  }
  [[noreturn]] void fail(const std::string& message) const {
    throw InputError(scene_.file, spec_.line,
                     cat("[[check]] '", spec_.name, "' (kind ", spec_.kind, "): ", message));
  }
  std::string text(const std::string& key, const std::string& fallback) const {
    const auto it = spec_.strings.find(key);
    if (it != spec_.strings.end()) return it->second;
    if (spec_.numbers.count(key)) fail("'" + key + "' must be a word, not a number");
    return fallback;
  }
  std::string choice(const std::string& key, const std::vector<std::string>& choices,
                     const std::string& fallback) const {
    const std::string v = text(key, fallback);
    for (const auto& c : choices) {
      if (v == c) return v;
    }
    fail(cat("'", key, "' must be one of ", join(choices, ", "), ", got '", v, "'"));
  }
  double number(const std::string& key, std::optional<double> fallback, double lo) const {
    const auto it = spec_.numbers.find(key);
    if (it == spec_.numbers.end()) {
      if (spec_.strings.count(key)) fail("'" + key + "' must be a number");
      if (!fallback) fail("needs the number '" + key + "'");
      return *fallback;
    }
    if (it->second.size() != 1) fail("'" + key + "' must be a single number");
    if (!(it->second[0] >= lo)) fail(cat("'", key, "' must be >= ", lo));
    return it->second[0];
  }
  std::optional<Vec3> direction(const std::string& key) const {
    const auto it = spec_.numbers.find(key);
    if (it == spec_.numbers.end()) return std::nullopt;
    if (it->second.size() != 3) fail("'" + key + "' must be a vector [x, y, z]");
    const Vec3 v(it->second[0], it->second[1], it->second[2]);
    if (!(v.norm() > 0)) fail("'" + key + "' must not be zero");
    return v.normalized();
  }
  /// The label prefix of the blocks, checked to select at least one free particle.
  std::string prefix(bool required) const {
    const std::string p = text("label_prefix", "");
    if (p.empty() && required) fail("needs 'label_prefix' (the blocks' labels: prefix_0, ...)");
    for (const auto& particle : scene_.particles) {
      if (!particle.fixed && particle.driver < 0 && matchesPrefix(particle.label, p)) return p;
    }
    fail(p.empty() ? std::string("the scene has no free particle")
                   : "no free particle is labelled '" + p + "' or '" + p + "_...'");
  }

 private:
  const setup::Setup& scene_;
  const setup::CheckSpec& spec_;
};

}  // namespace polydem::run

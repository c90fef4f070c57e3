// The parameters of one [[check]], as its kind reads them. The scene reader has checked every
// parameter against its kind's declaration (scene/check_kinds/): a kind reads only what it
// declares, so that the declarations stay the whole truth.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "polydem/core/types.h"
#include "polydem/run/tracker.h"
#include "polydem/setup/setup.h"

namespace polydem::run {

class Params {
 public:
  Params(const setup::Setup& scene, const setup::CheckSpec& spec) : scene_(scene), spec_(spec) {}

  /// Throws InputError at the check's line.
  [[noreturn]] void fail(const std::string& message) const;
  /// The number `key`, or `fallback` when the scene leaves it out (an error without one).
  double number(const std::string& key, std::optional<double> fallback = std::nullopt) const;
  /// The unit vector `key`, or nothing when the scene leaves it out (an error if `required`).
  std::optional<Vec3> vector(const std::string& key, bool required = false) const;
  std::string text(const std::string& key, const std::string& fallback = "") const;
  /// The particles named by `particle` (one label, or several separated by commas), tracked.
  std::vector<Uid> particles(Tracker& tracker) const;

 private:
  /// Throws polydem::Error when the kind reads a key its declaration lacks (a programming error).
  void declared(const std::string& key) const;

  const setup::Setup& scene_;
  const setup::CheckSpec& spec_;
};

/// `name` with every character that is not a letter or digit replaced by '_': a series column.
std::string columnName(const std::string& name);

}  // namespace polydem::run

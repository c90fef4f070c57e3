#include "polydem/run/checks/params.h"

#include <sstream>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/run/checks.h"
#include "polydem/scene/check_kinds.h"

namespace polydem::run {

void Params::fail(const std::string& message) const {
  throw InputError(scene_.file, spec_.line,
                   cat("[[check]] '", spec_.name, "' (kind ", spec_.kind, "): ", message));
}

double Params::number(const std::string& key, std::optional<double> fallback) const {
  declared(key);
  const auto it = spec_.numbers.find(key);
  if (it == spec_.numbers.end()) {
    if (fallback) return *fallback;
    fail("needs the number '" + key + "'");
  }
  if (it->second.size() != 1) fail("'" + key + "' must be a single number");
  return it->second[0];
}

std::optional<Vec3> Params::vector(const std::string& key, bool required) const {
  declared(key);
  const auto it = spec_.numbers.find(key);
  if (it == spec_.numbers.end()) {
    if (required) fail("needs the vector '" + key + "' = [x, y, z]");
    return std::nullopt;
  }
  if (it->second.size() != 3) fail("'" + key + "' must be a vector [x, y, z]");
  const Vec3 v(it->second[0], it->second[1], it->second[2]);
  if (!(v.norm() > 0)) fail("'" + key + "' must not be zero");
  return v.normalized();
}

std::string Params::text(const std::string& key, const std::string& fallback) const {
  declared(key);
  const auto it = spec_.strings.find(key);
  return it == spec_.strings.end() ? fallback : it->second;
}

std::vector<Uid> Params::particles(Tracker& tracker) const {
  const std::string list = text("particle");
  if (list.empty()) fail("needs 'particle' = \"label\" (or \"a,b,c\")");
  std::vector<Uid> uids;
  std::stringstream in(list);
  std::string label;
  while (std::getline(in, label, ',')) {
    label.erase(0, label.find_first_not_of(' '));
    label.erase(label.find_last_not_of(' ') + 1);
    const Uid uid = uidOfLabel(scene_, label);
    if (uid == 0) fail("no particle is labelled '" + label + "'");
    tracker.track(uid);
    uids.push_back(uid);
  }
  return uids;
}

void Params::declared(const std::string& key) const {
  const scene::CheckKind* kind = scene::findCheckKind(spec_.kind);
  if (!kind || !scene::findCheckParam(*kind, key)) {
    throw Error(cat("check kind '", spec_.kind, "' reads '", key, "', which its declaration (",
                    "module/scene/check_kinds/", spec_.kind, ".cpp) does not declare"));
  }
}

std::string columnName(const std::string& name) {
  std::string out;
  for (char c : name) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return out;
}

}  // namespace polydem::run

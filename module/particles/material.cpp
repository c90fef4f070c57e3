#include "polydem/particles/material.h"

#include <algorithm>

#include "polydem/core/error.h"

namespace polydem::particles {

int MaterialTable::add(const Material& m) {
  if (indexOf(m.name) >= 0) throw Error("material '" + m.name + "' defined twice");
  materials_.push_back(m);
  return static_cast<int>(materials_.size() - 1);
}

int MaterialTable::indexOf(const std::string& name) const {
  for (std::size_t i = 0; i < materials_.size(); ++i) {
    if (materials_[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

std::vector<double> MaterialTable::densities() const {
  std::vector<double> out;
  for (const auto& m : materials_) out.push_back(m.density);
  return out;
}

void MaterialTable::setInteraction(int a, int b, const ContactProperties& p) {
  explicit_[{std::min(a, b), std::max(a, b)}] = p;
}

namespace {
ContactProperties combine(const Material& a, const Material& b) {
  ContactProperties p;
  p.kn = std::min(a.kn, b.kn);
  p.ks = std::min(a.ks, b.ks);
  p.penalty = std::min(a.penalty, b.penalty);
  p.jkn = std::min(a.jkn, b.jkn);
  p.jks = std::min(a.jks, b.jks);
  p.friction_angle = std::min(a.friction_angle, b.friction_angle);
  p.cohesion = std::min(a.cohesion, b.cohesion);
  p.normal_damping = 0.5 * (a.normal_damping + b.normal_damping);
  return p;
}
}  // namespace

void MaterialTable::finalize() {
  const std::size_t n = size();
  table_.assign(n * n, {});
  for (std::size_t a = 0; a < n; ++a) {
    for (std::size_t b = 0; b < n; ++b) {
      const auto it = explicit_.find({std::min(a, b), std::max(a, b)});
      table_[a * n + b] =
          it != explicit_.end() ? it->second : combine(materials_[a], materials_[b]);
    }
  }
}

}  // namespace polydem::particles

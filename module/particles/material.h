// Materials and the contact properties of a pair of materials.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace polydem::particles {

struct Material {
  std::string name;
  double density = 0.0;         // kg/m^3
  double kn = 0.0;              // normal spring stiffness, N/m
  double ks = 0.0;              // tangential spring stiffness, N/m
  double friction_angle = 0.0;  // degrees
  double cohesion = 0.0;        // N (the C of Zhao eq. 35)
  double normal_damping = 0.0;  // viscous normal damping, fraction of critical
  double local_damping = 0.0;   // 3DEC local non-viscous damping coefficient, 0..0.8
  double penalty = 0.0;         // Pa: normal penalty of the potential kernels (Zhao eq. 13)
  double jkn = 0.0;             // Pa/m: normal stiffness per area of face contacts (0: use kn)
  double jks = 0.0;             // Pa/m: shear stiffness per area of face contacts (0: use ks)
};

/// What the contact law uses for one pair.
struct ContactProperties {
  double kn = 0.0, ks = 0.0;
  double friction_angle = 0.0;  // degrees
  double cohesion = 0.0;
  double normal_damping = 0.0;
  double penalty = 0.0;
  double jkn = 0.0, jks = 0.0;  // Pa/m, sub-contact model's face contacts (0: kn, ks per pair)
};

class MaterialTable {
 public:
  /// Adds a material; returns its index. Names must be unique.
  int add(const Material& m);
  int indexOf(const std::string& name) const;  // -1 if absent
  std::size_t size() const { return materials_.size(); }
  const Material& operator[](std::size_t i) const { return materials_[i]; }
  std::vector<double> densities() const;

  /// Properties for a contact between materials a and b: an explicit interaction if the scene gave
  /// one, otherwise the material's own values when a == b, and for two different materials the
  /// softer spring (min of kn, ks, penalty), the lower friction and cohesion, and the mean damping.
  const ContactProperties& pair(int a, int b) const { return table_[a * size() + b]; }
  void setInteraction(int a, int b, const ContactProperties& p);

  /// Builds the pair table; call after the last add() / setInteraction().
  void finalize();

 private:
  std::vector<Material> materials_;
  std::map<std::pair<int, int>, ContactProperties> explicit_;
  std::vector<ContactProperties> table_;
};

}  // namespace polydem::particles

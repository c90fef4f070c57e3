// The fields a snapshot can carry, declared once with the setup that chooses them: the scene
// reader checks `[output] fields` and `contact_fields` against these lists, Python's scene builder
// goes through the reader, the HDF5 snapshot writer (output/snapshot_h5.h) writes them
// with these types and units, and docs/output-files.md describes them.
#pragma once

#include <string>
#include <vector>

namespace polydem::setup {

/// Element type of a field in the file.
enum class FieldType { kFloat64, kUInt64, kInt32, kUInt8 };

struct SnapshotField {
  const char* name;
  int components;  // 1 (scalar) or 3 (vector)
  FieldType type;
  const char* units;  // empty for counts, indices and flags
  const char* description;
};

/// Per-particle fields, written once per face (cell data: the cells are the faces), and the
/// faces' own field `joint`.
inline const std::vector<SnapshotField> kParticleFields = {
    {"uid", 1, FieldType::kUInt64, "", "particle uid"},
    {"rank", 1, FieldType::kInt32, "", "MPI rank owning the particle"},
    {"material", 1, FieldType::kInt32, "", "index into the scene's [[material]] list"},
    {"fixed", 1, FieldType::kUInt8, "", "1 for fixed and driven bodies"},
    {"speed", 1, FieldType::kFloat64, "m/s", "|velocity|"},
    {"velocity", 3, FieldType::kFloat64, "m/s", "velocity of the centroid"},
    {"angular_velocity", 3, FieldType::kFloat64, "rad/s", "angular velocity, world frame"},
    {"displacement", 3, FieldType::kFloat64, "m", "centroid displacement since the start"},
    {"position", 3, FieldType::kFloat64, "m", "centroid"},
    {"contact_count", 1, FieldType::kInt32, "", "touching contacts of a free particle"},
    {"force", 3, FieldType::kFloat64, "N", "resultant contact force on a free particle"},
    {"joint", 1, FieldType::kInt32, "",
     "per face: index into the scene's [[joint]] list of the joint whose plane made the face; -1: "
     "on no joint"},
    {"pressure", 1, FieldType::kFloat64, "Pa",
     "per face: the mean water pressure on it ([water]: the hydrostatic pressure integrated over "
     "the wetted part, divided by the face's area); 0 on faces without water"},
};

/// Per-contact fields, written once per contact point (point data).
inline const std::vector<SnapshotField> kContactFields = {
    {"uid_a", 1, FieldType::kUInt64, "", "lower uid of the pair"},
    {"uid_b", 1, FieldType::kUInt64, "", "higher uid of the pair"},
    {"rank", 1, FieldType::kInt32, "", "MPI rank that wrote the contact"},
    {"normal", 3, FieldType::kFloat64, "", "unit normal, from B into A"},
    {"normal_force", 1, FieldType::kFloat64, "N", "normal force magnitude (>= 0)"},
    {"shear_force", 3, FieldType::kFloat64, "N", "shear force on A"},
    {"force", 3, FieldType::kFloat64, "N", "total force on A: normal_force * normal + shear"},
    {"joint", 1, FieldType::kInt32, "",
     "index into the scene's [[joint]] list of the joint whose properties the contact took; -1: "
     "the material pair's"},
};

/// Fields written when the scene does not choose: all of them but position (the faces show it).
inline const std::vector<std::string> kDefaultParticleFields = {
    "uid",          "rank",          "material", "fixed", "speed",   "velocity", "angular_velocity",
    "displacement", "contact_count", "force",    "joint", "pressure"};
inline const std::vector<std::string> kDefaultContactFields = {
    "uid_a", "uid_b", "rank", "normal", "normal_force", "shear_force", "force", "joint"};

/// The declaration of `name` in `fields`, or null.
inline const SnapshotField* findField(const std::vector<SnapshotField>& fields,
                                      const std::string& name) {
  for (const auto& f : fields) {
    if (name == f.name) return &f;
  }
  return nullptr;
}

/// "unknown field 'NAME' (known: uid, rank, ...)" for a name not in `fields`, else "".
inline std::string unknownField(const std::vector<SnapshotField>& fields, const std::string& name) {
  if (findField(fields, name)) return "";
  std::string known;
  for (const auto& f : fields) known += (known.empty() ? "" : ", ") + std::string(f.name);
  return "unknown field '" + name + "' (known: " + known + ")";
}

}  // namespace polydem::setup

#include "io/snapshot_fields.h"

namespace polydem::io {

const SnapshotField* findField(const std::vector<SnapshotField>& fields, const std::string& name) {
  for (const auto& f : fields) {
    if (name == f.name) return &f;
  }
  return nullptr;
}

std::string unknownField(const std::vector<SnapshotField>& fields, const std::string& name) {
  if (findField(fields, name)) return "";
  std::string known;
  for (const auto& f : fields) known += (known.empty() ? "" : ", ") + std::string(f.name);
  return "unknown field '" + name + "' (known: " + known + ")";
}

}  // namespace polydem::io

#include "polydem/output/xdmf_writer.h"

#include <cstdio>

#include "polydem/core/strings.h"
#include "polydem/setup/snapshot_fields.h"

namespace polydem::output {

namespace {

std::string formatTime(double time) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", time);
  return buffer;
}

/// NumberType and Precision of an XDMF DataItem.
std::string numberType(setup::FieldType type) {
  switch (type) {
    case setup::FieldType::kFloat64:
      return R"(NumberType="Float" Precision="8")";
    case setup::FieldType::kUInt64:
      return R"(NumberType="UInt" Precision="8")";
    case setup::FieldType::kInt32:
      return R"(NumberType="Int" Precision="4")";
    case setup::FieldType::kUInt8:
      return R"(NumberType="UChar" Precision="1")";
  }
  return "";
}

std::string dataItem(const std::string& dims, const std::string& type, const std::string& file,
                     const std::string& dataset) {
  return cat("        <DataItem Dimensions=\"", dims, "\" ", type, " Format=\"HDF\">", file, ":",
             dataset, "</DataItem>\n");
}

std::string dims(std::uint64_t rows, int components) {
  return components == 1 ? cat(rows) : cat(rows, " ", components);
}

/// The attributes of a grid: `fields` of `declared`, datasets under `group`, `rows` rows.
std::string attributes(const std::vector<setup::SnapshotField>& declared,
                       const std::vector<std::string>& fields, const char* center,
                       const std::string& file, const std::string& group, std::uint64_t rows) {
  std::string out;
  for (const auto& name : fields) {
    const setup::SnapshotField* f = setup::findField(declared, name);
    if (!f) continue;  // the scene reader refuses unknown names; nothing to describe
    out += cat("      <Attribute Name=\"", f->name, "\" AttributeType=\"",
               f->components == 1 ? "Scalar" : "Vector", "\" Center=\"", center, "\">\n");
    out += dataItem(dims(rows, f->components), numberType(f->type), file, group + "/" + f->name);
    out += "      </Attribute>\n";
  }
  return out;
}

std::string header(const char* name) {
  return cat(
      "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n<Xdmf Version=\"2.0\">\n"
      "  <Domain>\n    <Grid Name=\"",
      name, "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n");
}

const char* const kFooter = "    </Grid>\n  </Domain>\n</Xdmf>\n";

std::string gridStart(std::int64_t step, double time) {
  char name[32];
  std::snprintf(name, sizeof name, "step_%010lld", static_cast<long long>(step));
  return cat("     <Grid Name=\"", name, "\" GridType=\"Uniform\">\n      <Time Value=\"",
             formatTime(time), "\"/>\n");
}

const std::string kFloat = numberType(setup::FieldType::kFloat64);
const std::string kInt64 = R"(NumberType="Int" Precision="8")";

}  // namespace

std::string xdmfParticleCollection(const std::map<std::int64_t, XdmfSnapshot>& snapshots,
                                   const std::vector<std::string>& fields) {
  std::string out = header("particles");
  for (const auto& [step, s] : snapshots) {
    out += gridStart(step, s.time);
    out += cat("      <Topology TopologyType=\"Mixed\" NumberOfElements=\"", s.faces, "\">\n");
    out += dataItem(dims(s.topology, 1), kInt64, s.file, "/mesh/topology");
    out += "      </Topology>\n      <Geometry GeometryType=\"XYZ\">\n";
    out += dataItem(dims(s.points, 3), kFloat, s.file, "/mesh/points");
    out += "      </Geometry>\n";
    out += attributes(setup::kParticleFields, fields, "Cell", s.file, "/faces", s.faces);
    out += "     </Grid>\n";
  }
  return out + kFooter;
}

std::string xdmfContactCollection(const std::map<std::int64_t, XdmfSnapshot>& snapshots,
                                  const std::vector<std::string>& fields) {
  std::string out = header("contacts");
  for (const auto& [step, s] : snapshots) {
    if (s.contacts == 0) continue;
    out += gridStart(step, s.time);
    out += cat("      <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"", s.contacts,
               "\" NodesPerElement=\"1\">\n");
    out += dataItem(dims(s.contacts, 1), kInt64, s.file, "/contacts/vertex");
    out += "      </Topology>\n      <Geometry GeometryType=\"XYZ\">\n";
    out += dataItem(dims(s.contacts, 3), kFloat, s.file, "/contacts/point");
    out += "      </Geometry>\n";
    out += attributes(setup::kContactFields, fields, "Node", s.file, "/contacts", s.contacts);
    out += "     </Grid>\n";
  }
  return out + kFooter;
}

}  // namespace polydem::output

// Bolt lines as VTK PolyData, one file per snapshot (bolt_output.h).
#include "polydem/run/bolt_output.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "polydem/core/error.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/output/output_file.h"

namespace polydem::run {

namespace {

// The text of a file written under a temporary name and renamed into place (readers see the old
// file or the new one, never half of one).
void writeAtomically(const std::string& path, const std::string& text) {
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary);
    out << text;
    if (!out.flush()) throw Error(cat("cannot write ", temporary));
  }
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec) throw Error(cat("cannot rename ", temporary, " to ", path, ": ", ec.message()));
}

template <typename T, typename F>
std::string dataArray(const char* type, const char* name, int components,
                      const std::vector<sim::BoltLine>& lines, F value) {
  std::ostringstream out;
  out.precision(17);
  out << "        <DataArray type=\"" << type << "\" Name=\"" << name << "\" NumberOfComponents=\""
      << components << "\" format=\"ascii\">";
  for (const auto& l : lines) out << ' ' << static_cast<T>(value(l));
  out << "</DataArray>\n";
  return out.str();
}

std::string polyData(const std::vector<sim::BoltLine>& lines,
                     const std::vector<std::int32_t>& joints, double time) {
  std::ostringstream out;
  out.precision(17);
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"1.0\" "
         "byte_order=\"LittleEndian\">\n  <PolyData>\n    <FieldData>\n"
      << "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" "
         "format=\"ascii\">"
      << time << "</DataArray>\n    </FieldData>\n"
      << "    <Piece NumberOfPoints=\"" << 2 * lines.size() << "\" NumberOfVerts=\"0\" "
      << "NumberOfLines=\"" << lines.size() << "\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n"
      << "      <Points>\n        <DataArray type=\"Float64\" NumberOfComponents=\"3\" "
         "format=\"ascii\">";
  for (const auto& l : lines) {
    out << ' ' << l.from.x() << ' ' << l.from.y() << ' ' << l.from.z() << ' ' << l.to.x() << ' '
        << l.to.y() << ' ' << l.to.z();
  }
  out << "</DataArray>\n      </Points>\n      <Lines>\n"
      << "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">";
  for (std::size_t k = 0; k < 2 * lines.size(); ++k) out << ' ' << k;
  out << "</DataArray>\n        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">";
  for (std::size_t k = 1; k <= lines.size(); ++k) out << ' ' << 2 * k;
  out << "</DataArray>\n      </Lines>\n      <CellData Scalars=\"axial_force\">\n";
  out << dataArray<double>("Float64", "axial_force", 1, lines,
                           [](const sim::BoltLine& l) { return l.axial_force; });
  out << dataArray<double>("Float64", "shear_force", 1, lines,
                           [](const sim::BoltLine& l) { return l.shear_force; });
  out << dataArray<std::int32_t>("Int32", "bolt", 1, lines,
                                 [](const sim::BoltLine& l) { return l.bolt; });
  std::size_t k = 0;
  out << dataArray<std::int32_t>("Int32", "joint", 1, lines,
                                 [&](const sim::BoltLine&) { return joints[k++]; });
  out << dataArray<int>("UInt8", "broken", 1, lines,
                        [](const sim::BoltLine& l) { return l.broken ? 1 : 0; });
  out << "      </CellData>\n    </Piece>\n  </PolyData>\n</VTKFile>\n";
  return out.str();
}

}  // namespace

BoltOutput::BoltOutput(const std::string& dir, const sim::Simulation& sim)
    : dir_(dir), root_(mpi::rank(sim.comm()) == 0), any_(!sim.bolts().empty()) {
  if (!any_ || !root_) return;
  std::filesystem::create_directories(dir_ + "/bolts");
  std::ifstream old(dir_ + "/bolts.pvd");
  for (std::string line; std::getline(old, line);) {
    if (line.find("<DataSet") != std::string::npos) kept_.push_back(line);
  }
}

void BoltOutput::write(const sim::Simulation& sim) {
  if (!any_) return;
  const std::vector<sim::BoltLine> lines = sim.boltLines();  // collective
  // Rank 0 writes alone; a failure (a full disk) ends every rank here, not in the next collective.
  std::string error;
  if (root_) {
    try {
      writeFiles(sim, lines);
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  output::throwIfAnyRankFailed(error, sim.comm());
}

void BoltOutput::writeFiles(const sim::Simulation& sim, const std::vector<sim::BoltLine>& lines) {
  if (first_) {
    // A restart continues the collection: earlier entries up to this time stay.
    std::vector<std::string> keep;
    for (const auto& line : kept_) {
      const auto at = line.find("timestep=\"");
      if (at == std::string::npos) continue;
      if (std::stod(line.substr(at + 10)) < sim.time()) keep.push_back(line);
    }
    kept_ = std::move(keep);
    first_ = false;
  }
  std::vector<std::int32_t> joints;
  for (std::size_t k = 0; k < lines.size(); ++k) {
    joints.push_back(k > 0 && lines[k].bolt == lines[k - 1].bolt ? joints.back() + 1 : 1);
  }
  char name[64];
  std::snprintf(name, sizeof name, "bolts/bolts_%012lld.vtp",
                static_cast<long long>(sim.stepCount()));
  writeAtomically(dir_ + "/" + name, polyData(lines, joints, sim.time()));
  if (entries_.empty() || entries_.back().second != name) entries_.emplace_back(sim.time(), name);
  writeCollection();
}

void BoltOutput::writeCollection() const {
  std::ostringstream out;
  out.precision(17);
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\">\n"
         "  <Collection>\n";
  for (const auto& line : kept_) out << line << "\n";
  for (const auto& [time, file] : entries_) {
    out << "    <DataSet timestep=\"" << time << "\" part=\"0\" file=\"" << file << "\"/>\n";
  }
  out << "  </Collection>\n</VTKFile>\n";
  writeAtomically(dir_ + "/bolts.pvd", out.str());
}

}  // namespace polydem::run

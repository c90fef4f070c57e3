#include "polydem/output/vtk_writer.h"

#include <array>
#include <cstdio>
#include <fstream>
#include <utility>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/output/output_file.h"
#include "polydem/output/vtk_xml.h"

namespace polydem::output {

// ---------------------------------------------------------------------------------------------
// PolyhedraBatch

void PolyhedraBatch::addParticle(const ParticleFields& fields,
                                 std::span<const Vec3> world_vertices) {
  particles.push_back(fields);
  points.insert(points.end(), world_vertices.begin(), world_vertices.end());
  point_end.push_back(static_cast<std::int64_t>(points.size()));
  particle_face_end.push_back(static_cast<std::int64_t>(face_end.size()));
}

void PolyhedraBatch::addFace(std::span<const int> vertices, std::int32_t joint, double pressure) {
  if (particles.empty()) throw Error("PolyhedraBatch::addFace: no particle added yet");
  const std::int64_t first = point_end.size() > 1 ? point_end[point_end.size() - 2] : 0;
  const std::int64_t count = point_end.back() - first;
  if (vertices.size() < 3) {
    throw Error(cat("snapshot: a face of particle ", particles.back().uid, " has ", vertices.size(),
                    " vertices (a polygon needs at least 3)"));
  }
  for (const int v : vertices) {
    if (v < 0 || v >= count) {
      throw Error(cat("snapshot: a face of particle ", particles.back().uid, " uses vertex ", v,
                      " of ", count));
    }
    connectivity.push_back(first + v);
  }
  face_end.push_back(static_cast<std::int64_t>(connectivity.size()));
  face_joint.push_back(joint);
  face_pressure.push_back(pressure);
  particle_face_end.back() = static_cast<std::int64_t>(face_end.size());
}

void PolyhedraBatch::addParticle(const ParticleFields& fields, std::span<const Vec3> world_vertices,
                                 const std::vector<std::vector<int>>& faces) {
  addParticle(fields, world_vertices);
  for (const auto& face : faces) addFace(face);
}

void PolyhedraBatch::clear() {
  particles.clear();
  points.clear();
  point_end.clear();
  connectivity.clear();
  face_end.clear();
  particle_face_end.clear();
  face_joint.clear();
  face_pressure.clear();
}

namespace {

using vtk::array;
using vtk::Piece;
using vtk::Section;

// ---------------------------------------------------------------------------------------------
// The particle and contact pieces

template <typename T, int N, typename F>
std::vector<T> faceValues(const PolyhedraBatch& b, F value) {
  std::vector<T> out;
  out.reserve(b.faceCount() * N);
  std::int64_t face = 0;
  for (std::size_t p = 0; p < b.particles.size(); ++p) {
    const auto v = value(b.particles[p]);
    for (; face < b.particle_face_end[p]; ++face) out.insert(out.end(), v.begin(), v.end());
  }
  return out;
}

std::array<double, 3> components(const Vec3& v) {
  return {v.x(), v.y(), v.z()};
}

std::vector<double> flatten(const std::vector<Vec3>& v) {
  std::vector<double> out;
  out.reserve(3 * v.size());
  for (const auto& x : v) out.insert(out.end(), {x.x(), x.y(), x.z()});
  return out;
}

void validate(const PolyhedraBatch& b) {
  const std::size_t n = b.particles.size();
  if (b.point_end.size() != n || b.particle_face_end.size() != n ||
      (n > 0 && (b.point_end.back() != static_cast<std::int64_t>(b.points.size()) ||
                 b.particle_face_end.back() != static_cast<std::int64_t>(b.face_end.size()))) ||
      (n == 0 && (!b.points.empty() || !b.face_end.empty())) ||
      (!b.face_end.empty() &&
       b.face_end.back() != static_cast<std::int64_t>(b.connectivity.size())) ||
      b.face_joint.size() != b.face_end.size() || b.face_pressure.size() != b.face_end.size()) {
    throw Error("snapshot: inconsistent PolyhedraBatch (fill it with addParticle/addFace)");
  }
  const auto points = static_cast<std::int64_t>(b.points.size());
  for (const std::int64_t i : b.connectivity) {
    if (i < 0 || i >= points) throw Error(cat("snapshot: face vertex ", i, " of ", points));
  }
}

/// The generators of the returned piece refer to `b`, which must outlive it.
Piece particlePiece(const PolyhedraBatch& b, int rank) {
  validate(b);
  Piece piece;
  piece.points = b.points.size();
  piece.polys = b.faceCount();
  const std::size_t cells = piece.polys;
  using P = const ParticleFields&;
  Section cell{"CellData", " Scalars=\"speed\" Vectors=\"velocity\"", {}};
  cell.arrays.push_back(array<std::uint64_t>("uid", 1, cells, [&b] {
    return faceValues<std::uint64_t, 1>(b, [](P p) { return std::array<std::uint64_t, 1>{p.uid}; });
  }));
  cell.arrays.push_back(array<std::int32_t>("rank", 1, cells, [&b, rank] {
    return faceValues<std::int32_t, 1>(b, [rank](P) { return std::array<std::int32_t, 1>{rank}; });
  }));
  cell.arrays.push_back(array<double>("velocity", 3, cells, [&b] {
    return faceValues<double, 3>(b, [](P p) { return components(p.velocity); });
  }));
  cell.arrays.push_back(array<double>("angular_velocity", 3, cells, [&b] {
    return faceValues<double, 3>(b, [](P p) { return components(p.angular_velocity); });
  }));
  cell.arrays.push_back(array<double>("speed", 1, cells, [&b] {
    return faceValues<double, 1>(b, [](P p) { return std::array<double, 1>{p.velocity.norm()}; });
  }));
  cell.arrays.push_back(array<double>("displacement", 3, cells, [&b] {
    return faceValues<double, 3>(b, [](P p) { return components(p.displacement); });
  }));
  cell.arrays.push_back(array<std::uint8_t>("fixed", 1, cells, [&b] {
    return faceValues<std::uint8_t, 1>(
        b, [](P p) { return std::array<std::uint8_t, 1>{static_cast<std::uint8_t>(p.fixed)}; });
  }));
  cell.arrays.push_back(array<std::int32_t>("joint", 1, cells, [&b] { return b.face_joint; }));
  cell.arrays.push_back(array<double>("pressure", 1, cells, [&b] { return b.face_pressure; }));
  piece.sections.push_back(std::move(cell));
  piece.sections.push_back({"Points", "", {array<double>("Points", 3, b.points.size(), [&b] {
                              return flatten(b.points);
                            })}});
  piece.sections.push_back(
      {"Polys",
       "",
       {array<std::int64_t>("connectivity", 1, b.connectivity.size(),
                            [&b] { return b.connectivity; }),
        array<std::int64_t>("offsets", 1, b.face_end.size(), [&b] { return b.face_end; })}});
  return piece;
}

template <typename T, typename F>
std::vector<T> contactValues(const ContactBatch& c, F value) {
  std::vector<T> out;
  out.reserve(c.contacts.size() * 3);
  for (const auto& r : c.contacts) {
    const auto v = value(r);
    out.insert(out.end(), v.begin(), v.end());
  }
  return out;
}

/// The generators of the returned piece refer to `c`, which must outlive it.
Piece contactPiece(const ContactBatch& c, int rank) {
  Piece piece;
  const std::size_t n = c.contacts.size();
  piece.points = n;
  piece.verts = n;
  using R = const ContactRecord&;
  Section data{"PointData", " Scalars=\"normal_force\" Vectors=\"normal\"", {}};
  data.arrays.push_back(array<std::uint64_t>("uid_a", 1, n, [&c] {
    return contactValues<std::uint64_t>(c,
                                        [](R r) { return std::array<std::uint64_t, 1>{r.uid_a}; });
  }));
  data.arrays.push_back(array<std::uint64_t>("uid_b", 1, n, [&c] {
    return contactValues<std::uint64_t>(c,
                                        [](R r) { return std::array<std::uint64_t, 1>{r.uid_b}; });
  }));
  data.arrays.push_back(array<std::int32_t>("rank", 1, n, [&c, rank] {
    return contactValues<std::int32_t>(c, [rank](R) { return std::array<std::int32_t, 1>{rank}; });
  }));
  data.arrays.push_back(array<double>("normal", 3, n, [&c] {
    return contactValues<double>(c, [](R r) { return components(r.normal); });
  }));
  data.arrays.push_back(array<double>("normal_force", 1, n, [&c] {
    return contactValues<double>(c, [](R r) { return std::array<double, 1>{r.normal_force}; });
  }));
  data.arrays.push_back(array<double>("shear_force", 3, n, [&c] {
    return contactValues<double>(c, [](R r) { return components(r.shear_force); });
  }));
  data.arrays.push_back(array<std::int32_t>("joint", 1, n, [&c] {
    return contactValues<std::int32_t>(c, [](R r) { return std::array<std::int32_t, 1>{r.joint}; });
  }));
  piece.sections.push_back(std::move(data));
  piece.sections.push_back({"Points", "", {array<double>("Points", 3, n, [&c] {
                              return contactValues<double>(c,
                                                           [](R r) { return components(r.point); });
                            })}});
  auto iota = [n](std::int64_t first) {
    std::vector<std::int64_t> v(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = first + static_cast<std::int64_t>(i);
    return v;
  };
  piece.sections.push_back({"Verts",
                            "",
                            {array<std::int64_t>("connectivity", 1, n, [=] { return iota(0); }),
                             array<std::int64_t>("offsets", 1, n, [=] { return iota(1); })}});
  return piece;
}

std::string stepName(const char* kind, std::int64_t step) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%s_%010lld", kind, static_cast<long long>(step));
  return buffer;
}

std::string pieceName(const char* kind, std::int64_t step, int rank) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "_r%04d.vtp", rank);
  return stepName(kind, step) + buffer;
}

std::string formatTimestep(double time) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", time);
  return buffer;
}

/// The value of attribute `name` in one XML element's text, or nullopt.
std::optional<std::string> attribute(const std::string& element, const std::string& name) {
  const std::string key = " " + name + "=\"";
  const auto start = element.find(key);
  if (start == std::string::npos) return std::nullopt;
  const auto begin = start + key.size();
  const auto end = element.find('"', begin);
  if (end == std::string::npos) return std::nullopt;
  return element.substr(begin, end - begin);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// SnapshotWriter

SnapshotWriter::SnapshotWriter(std::string dir, MPI_Comm comm)
    : SnapshotWriter(std::move(dir), comm, Options{}) {}

SnapshotWriter::SnapshotWriter(std::string dir, MPI_Comm comm, Options options)
    : dir_(std::move(dir)), comm_(comm), options_(options) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
  particles_.path = particleCollectionPath();
  contacts_.path = contactCollectionPath();
  std::string error;
  // Rank 0 first, so that the others find the directory on a shared file system.
  if (rank_ == 0) {
    try {
      createDirectories(dir_ + "/snapshots");
      // Both collections exist from the start (empty on a fresh run), so a collection left by
      // an earlier run in the same directory never outlives this one's start.
      if (options_.resume_after_step) {
        loadCollection(particles_, *options_.resume_after_step);
        loadCollection(contacts_, *options_.resume_after_step);
      }
      writeCollection(particles_);
      writeCollection(contacts_);
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  throwIfAnyRankFailed(error, comm_);
  if (rank_ != 0) {
    try {
      createDirectories(dir_ + "/snapshots");
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  throwIfAnyRankFailed(error, comm_);
}

std::string SnapshotWriter::particleCollectionPath() const {
  return dir_ + "/snapshots.pvd";
}
std::string SnapshotWriter::contactCollectionPath() const {
  return dir_ + "/contacts.pvd";
}

std::string SnapshotWriter::particlePath(std::int64_t step, int rank) const {
  return dir_ + "/snapshots/" +
         (rank < 0 ? stepName("particles", step) + ".pvtp" : pieceName("particles", step, rank));
}

std::string SnapshotWriter::contactPath(std::int64_t step, int rank) const {
  return dir_ + "/snapshots/" +
         (rank < 0 ? stepName("contacts", step) + ".pvtp" : pieceName("contacts", step, rank));
}

void SnapshotWriter::write(double time, std::int64_t step, const PolyhedraBatch& particles,
                           const ContactBatch* contacts) {
  int any_contacts = contacts != nullptr;
  MPI_Allreduce(MPI_IN_PLACE, &any_contacts, 1, MPI_INT, MPI_MAX, comm_);
  const ContactBatch none;
  if (!contacts) contacts = &none;

  // 1. Every rank its pieces.
  const bool binary = options_.encoding == VtkEncoding::kBase64;
  std::string error;
  try {
    vtk::writePiece(particlePath(step, rank_), particlePiece(particles, rank_), binary);
    if (any_contacts) {
      vtk::writePiece(contactPath(step, rank_), contactPiece(*contacts, rank_), binary);
    }
  } catch (const std::exception& e) {
    error = e.what();
  }
  throwIfAnyRankFailed(error, comm_);

  // 2. Rank 0 the headers, then the collections: a collection never lists a missing file.
  if (rank_ == 0) {
    const Collection particles_before = particles_, contacts_before = contacts_;
    try {
      auto publish = [&](Collection& collection, const char* kind, const Piece& piece,
                         const std::string& header_path) {
        std::vector<std::string> sources;
        for (int r = 0; r < size_; ++r) sources.push_back(pieceName(kind, step, r));
        vtk::writeParallelHeader(header_path, piece, sources);
        collection.entries[step] = {time, "snapshots/" + stepName(kind, step) + ".pvtp"};
        writeCollection(collection);
      };
      // The header declares the arrays only; an empty batch gives the same declarations.
      publish(particles_, "particles", particlePiece(PolyhedraBatch{}, 0), particlePath(step));
      if (any_contacts) {
        publish(contacts_, "contacts", contactPiece(ContactBatch{}, 0), contactPath(step));
      }
    } catch (const std::exception& e) {
      particles_ = particles_before;
      contacts_ = contacts_before;
      error = e.what();
    }
  }
  throwIfAnyRankFailed(error, comm_);
}

void SnapshotWriter::loadCollection(Collection& collection, std::int64_t keep_up_to) const {
  collection.entries.clear();
  std::ifstream in(collection.path);
  if (!in) return;  // nothing written before the checkpoint
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.find("<DataSet") == std::string::npos) continue;
    const auto time = attribute(line, "timestep");
    const auto file = attribute(line, "file");
    const auto underscore = file ? file->rfind('_') : std::string::npos;
    const auto dot = file ? file->rfind(".pvtp") : std::string::npos;
    std::int64_t step = 0;
    bool ok =
        time && underscore != std::string::npos && dot != std::string::npos && dot > underscore;
    if (ok) {
      try {
        std::size_t used = 0;
        const std::string digits = file->substr(underscore + 1, dot - underscore - 1);
        step = std::stoll(digits, &used);
        ok = used == digits.size();
        if (ok && step <= keep_up_to) collection.entries[step] = {std::stod(*time), *file};
      } catch (const std::exception&) {
        ok = false;
      }
    }
    if (!ok) {
      throw Error(cat(collection.path, ":", line_number,
                      ": cannot resume: not a snapshot entry written by polydem"));
    }
  }
}

void SnapshotWriter::writeCollection(const Collection& collection) const {
  std::string text = vtk::fileHeader("Collection");
  text += "  <Collection>\n";
  for (const auto& [step, entry] : collection.entries) {
    text += cat("    <DataSet timestep=\"", formatTimestep(entry.first),
                "\" group=\"\" part=\"0\" file=\"", entry.second, "\"/>\n");
  }
  text += "  </Collection>\n</VTKFile>\n";
  writeFileAtomic(collection.path, text);
}

}  // namespace polydem::output

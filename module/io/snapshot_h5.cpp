#include "io/snapshot_h5.h"

#include <array>
#include <cstdio>
#include <filesystem>
#include <utility>

#include "core/error.h"
#include "core/strings.h"
#include "io/hdf5_file.h"
#include "io/output_file.h"
#include "io/snapshot_fields.h"

namespace polydem::io {

namespace {

using h5::Dataset;
using h5::File;
using h5::Info;
using h5::Slice;

/// Rows this rank writes of each table, and where they go: one allgather for all five tables.
enum Table { kParticles, kPoints, kFaces, kTopology, kContacts, kTables };

std::array<Slice, kTables> slices(const std::array<std::uint64_t, kTables>& rows, MPI_Comm comm) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  std::vector<std::uint64_t> all(static_cast<std::size_t>(ranks) * kTables);
  MPI_Allgather(rows.data(), kTables, MPI_UINT64_T, all.data(), kTables, MPI_UINT64_T, comm);
  std::array<Slice, kTables> out{};
  for (int t = 0; t < kTables; ++t) {
    out[t].rows = rows[t];
    for (int r = 0; r < ranks; ++r) {
      const std::uint64_t n = all[static_cast<std::size_t>(r) * kTables + t];
      if (r < rank) out[t].offset += n;
      out[t].total += n;
      out[t].max_rows = std::max(out[t].max_rows, n);
    }
  }
  return out;
}

/// Creates a dataset and writes this rank's rows in one collective call; kept in `open` until
/// File::finish() stores the checksums.
template <typename T>
void put(File& file, std::vector<Dataset>& open, const std::string& name, const Slice& slice,
         std::size_t cols, const std::vector<T>& data, const Info& info) {
  Dataset d = file.create<T>(name, slice.total, cols, info);
  d.write(data.data(), slice.offset, slice.rows);
  d.hash(data.data(), slice.offset, slice.rows);
  open.push_back(std::move(d));
}

void append(std::vector<double>& out, const Vec3& v) {
  out.insert(out.end(), {v.x(), v.y(), v.z()});
}

/// One value (or vector) per particle, repeated on each of its faces.
template <typename T, typename F>
std::vector<T> perFace(const PolyhedraBatch& b, F value) {
  std::vector<T> out, one;
  std::int64_t face = 0;
  for (std::size_t p = 0; p < b.particles.size(); ++p) {
    one.clear();
    value(b.particles[p], one);
    for (; face < b.particle_face_end[p]; ++face) out.insert(out.end(), one.begin(), one.end());
  }
  return out;
}

/// Writes the cell data `name` (a kParticleFields entry) of `b`.
void putParticleField(File& file, std::vector<Dataset>& open, const SnapshotField& f,
                      const Slice& faces, const PolyhedraBatch& b, int rank) {
  using P = const ParticleFields&;
  const std::string name = f.name;
  const std::string dataset = "/faces/" + name;
  const Info info{f.units, f.description};
  const auto cols = static_cast<std::size_t>(f.components);
  auto vector = [&](auto member) {
    put(file, open, dataset, faces, cols,
        perFace<double>(b, [member](P p, std::vector<double>& o) { append(o, p.*member); }), info);
  };
  if (name == "uid") {
    put(file, open, dataset, faces, cols,
        perFace<std::uint64_t>(b, [](P p, std::vector<std::uint64_t>& o) { o.push_back(p.uid); }),
        info);
  } else if (name == "rank" || name == "material" || name == "contact_count") {
    put(file, open, dataset, faces, cols,
        perFace<std::int32_t>(b,
                              [&](P p, std::vector<std::int32_t>& o) {
                                o.push_back(name == "rank"       ? rank
                                            : name == "material" ? p.material
                                                                 : p.contact_count);
                              }),
        info);
  } else if (name == "fixed") {
    put(file, open, dataset, faces, cols,
        perFace<std::uint8_t>(
            b, [](P p, std::vector<std::uint8_t>& o) { o.push_back(p.fixed ? 1 : 0); }),
        info);
  } else if (name == "speed") {
    put(file, open, dataset, faces, cols,
        perFace<double>(b, [](P p, std::vector<double>& o) { o.push_back(p.velocity.norm()); }),
        info);
  } else if (name == "velocity") {
    vector(&ParticleFields::velocity);
  } else if (name == "angular_velocity") {
    vector(&ParticleFields::angular_velocity);
  } else if (name == "displacement") {
    vector(&ParticleFields::displacement);
  } else if (name == "position") {
    vector(&ParticleFields::position);
  } else if (name == "force") {
    vector(&ParticleFields::force);
  } else {
    throw Error("snapshot: field '" + name + "' is declared but not written (a bug)");
  }
}

template <typename T, typename F>
std::vector<T> perContact(const ContactBatch& c, F value) {
  std::vector<T> out;
  for (const auto& r : c.contacts) value(r, out);
  return out;
}

void putContactField(File& file, std::vector<Dataset>& open, const SnapshotField& f,
                     const Slice& contacts, const ContactBatch& c, int rank) {
  using R = const ContactRecord&;
  const std::string name = f.name;
  const std::string dataset = "/contacts/" + name;
  const Info info{f.units, f.description};
  const auto cols = static_cast<std::size_t>(f.components);
  if (name == "uid_a" || name == "uid_b") {
    const bool a = name == "uid_a";
    put(file, open, dataset, contacts, cols,
        perContact<std::uint64_t>(
            c, [a](R r, std::vector<std::uint64_t>& o) { o.push_back(a ? r.uid_a : r.uid_b); }),
        info);
  } else if (name == "rank") {
    put(file, open, dataset, contacts, cols,
        perContact<std::int32_t>(c, [rank](R, std::vector<std::int32_t>& o) { o.push_back(rank); }),
        info);
  } else if (name == "normal_force") {
    put(file, open, dataset, contacts, cols,
        perContact<double>(c, [](R r, std::vector<double>& o) { o.push_back(r.normal_force); }),
        info);
  } else if (name == "normal" || name == "shear_force" || name == "force") {
    put(file, open, dataset, contacts, cols,
        perContact<double>(c,
                           [&name](R r, std::vector<double>& o) {
                             append(o, name == "normal" ? r.normal
                                       : name == "shear_force"
                                           ? r.shear_force
                                           : Vec3(r.normal_force * r.normal + r.shear_force));
                           }),
        info);
  } else {
    throw Error("snapshot: contact field '" + name + "' is declared but not written (a bug)");
  }
}

std::string joined(const std::vector<std::string>& names) {
  return join(names, ",");
}

}  // namespace

XdmfSnapshotWriter::XdmfSnapshotWriter(std::string dir, MPI_Comm comm, Options options)
    : dir_(std::move(dir)), comm_(comm), options_(std::move(options)) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
  if (options_.fields.empty()) options_.fields = kDefaultParticleFields;
  if (options_.contact_fields.empty()) options_.contact_fields = kDefaultContactFields;
  for (const auto& f : options_.fields) {
    if (auto problem = unknownField(kParticleFields, f); !problem.empty()) throw Error(problem);
  }
  for (const auto& f : options_.contact_fields) {
    if (auto problem = unknownField(kContactFields, f); !problem.empty()) throw Error(problem);
  }
  // Every rank must name the same directory: the files are opened collectively, and MPI-IO
  // waits forever on ranks that open different files.
  std::uint64_t length = dir_.size();
  MPI_Bcast(&length, 1, MPI_UINT64_T, 0, comm_);
  std::string root_dir(length, '\0');
  if (rank_ == 0) root_dir = dir_;
  MPI_Bcast(root_dir.data(), static_cast<int>(length), MPI_CHAR, 0, comm_);
  std::string error;
  if (root_dir != dir_) {
    error = cat("snapshots: rank ", rank_, " writes to ", dir_, " but rank 0 to ", root_dir,
                " (all ranks must use the same output directory)");
  }
  throwIfAnyRankFailed(error, comm_);
  // Rank 0 first, so that the others find the directory on a shared file system.
  if (rank_ == 0) {
    try {
      createDirectories(dir_ + "/snapshots");
      writeCollections();
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  throwIfAnyRankFailed(error, comm_);
}

std::string XdmfSnapshotWriter::particleCollectionPath() const {
  return dir_ + "/snapshots.xmf";
}
std::string XdmfSnapshotWriter::contactCollectionPath() const {
  return dir_ + "/contacts.xmf";
}

std::string XdmfSnapshotWriter::snapshotPath(std::int64_t step) const {
  char name[48];
  std::snprintf(name, sizeof name, "snapshot_%010lld.h5", static_cast<long long>(step));
  return dir_ + "/snapshots/" + name;
}

void XdmfSnapshotWriter::writeFile(const std::string& path, std::int64_t step, double time,
                                   const PolyhedraBatch& b, const ContactBatch& c,
                                   XdmfSnapshot& counts) const {
  // Mixed topology: each face is (3 = polygon, vertex count, vertex indices), the indices made
  // global by the points of lower ranks.
  const std::uint64_t faces = b.faceCount();
  const std::array<std::uint64_t, kTables> rows = {b.particleCount(), b.points.size(), faces,
                                                   2 * faces + b.connectivity.size(),
                                                   c.contacts.size()};
  const auto s = slices(rows, comm_);
  counts.points = s[kPoints].total;
  counts.faces = s[kFaces].total;
  counts.topology = s[kTopology].total;
  counts.contacts = s[kContacts].total;

  std::vector<std::int64_t> topology;
  topology.reserve(rows[kTopology]);
  const auto first_point = static_cast<std::int64_t>(s[kPoints].offset);
  std::int64_t begin = 0;
  for (const std::int64_t end : b.face_end) {
    topology.insert(topology.end(), {3, end - begin});
    for (std::int64_t i = begin; i < end; ++i) topology.push_back(first_point + b.connectivity[i]);
    begin = end;
  }
  std::vector<double> points, position, velocity, contact_points;
  for (const Vec3& p : b.points) append(points, p);
  std::vector<std::uint64_t> uid;
  std::vector<std::int64_t> face_count, vertex;
  std::int64_t previous_end = 0;
  for (std::size_t p = 0; p < b.particles.size(); ++p) {
    uid.push_back(b.particles[p].uid);
    face_count.push_back(b.particle_face_end[p] - previous_end);
    previous_end = b.particle_face_end[p];
    append(position, b.particles[p].position);
    append(velocity, b.particles[p].velocity);
  }
  for (std::size_t i = 0; i < c.contacts.size(); ++i) {
    append(contact_points, c.contacts[i].point);
    vertex.push_back(static_cast<std::int64_t>(s[kContacts].offset + i));
  }

  CheckpointIoOptions io;
  io.kind = "snapshot";
  const h5::ErrorSilencer quiet;  // HDF5's errors become exceptions, not printed stacks
  File file = File::create(path, comm_, io);
  std::vector<Dataset> open;
  file.createGroup("/mesh", "the faces of all blocks as polygons (XDMF Mixed topology)");
  put(file, open, "/mesh/points", s[kPoints], 3, points, {"m", "vertices, world frame"});
  put(file, open, "/mesh/topology", s[kTopology], 1, topology,
      {"", "per face: 3 (polygon), vertex count, indices into /mesh/points"});
  file.createGroup("/particles", "one row per particle");
  put(file, open, "/particles/uid", s[kParticles], 1, uid, {"", "particle uid"});
  put(file, open, "/particles/face_count", s[kParticles], 1, face_count,
      {"", "faces of the particle: its rows in /faces follow those of the previous rows"});
  put(file, open, "/particles/position", s[kParticles], 3, position, {"m", "centroid"});
  put(file, open, "/particles/velocity", s[kParticles], 3, velocity, {"m/s", "centroid velocity"});
  file.createGroup("/faces", "the chosen particle fields, one row per face (cell data)");
  for (const auto& name : options_.fields) {
    putParticleField(file, open, *findField(kParticleFields, name), s[kFaces], b, rank_);
  }
  file.createGroup("/contacts", "touching contacts: one row per contact point");
  put(file, open, "/contacts/point", s[kContacts], 3, contact_points, {"m", "contact point"});
  put(file, open, "/contacts/vertex", s[kContacts], 1, vertex, {"", "row index (vertex cells)"});
  for (const auto& name : options_.contact_fields) {
    putContactField(file, open, *findField(kContactFields, name), s[kContacts], c, rank_);
  }
  std::vector<Dataset*> all;
  for (auto& d : open) all.push_back(&d);
  file.finish(all);
  open.clear();  // the datasets must be closed before the file
  file.writeAttribute("/", "format", std::string("polydem-snapshot"));
  file.writeAttribute<std::int32_t>("/", "format_version", kSnapshotFormatVersion);
  file.writeAttribute<std::int64_t>("/", "step", step);
  file.writeAttribute<double>("/", "time", time);
  file.writeAttribute<std::int32_t>("/", "writer_ranks", size_);
  file.writeAttribute("/", "fields", joined(options_.fields));
  file.writeAttribute("/", "contact_fields", joined(options_.contact_fields));
  file.close();
}

void XdmfSnapshotWriter::write(double time, std::int64_t step, const PolyhedraBatch& particles,
                               const ContactBatch* contacts) {
  const ContactBatch none;
  if (!contacts) contacts = &none;
  const std::string path = snapshotPath(step), tmp = path + ".tmp";
  XdmfSnapshot counts;
  counts.time = time;
  counts.file = "snapshots/" + std::filesystem::path(path).filename().string();
  std::string error;
  try {
    writeFile(tmp, step, time, particles, *contacts, counts);  // throws on every rank alike
  } catch (const std::exception& e) {
    error = e.what();
  }
  if (rank_ == 0) {
    std::error_code ignored;
    if (!error.empty()) std::filesystem::remove(tmp, ignored);
    if (error.empty()) {
      std::error_code ec;
      std::filesystem::rename(tmp, path, ec);
      if (ec) error = cat("snapshot ", path, ": cannot rename the temporary file: ", ec.message());
    }
  }
  throwIfAnyRankFailed(error, comm_);

  // The collections list the file only once it is in place.
  if (rank_ == 0) {
    const auto before = snapshots_;
    try {
      snapshots_[step] = counts;
      writeCollections();
    } catch (const std::exception& e) {
      snapshots_ = before;
      error = e.what();
    }
  } else {
    snapshots_[step] = counts;
  }
  throwIfAnyRankFailed(error, comm_);
}

void XdmfSnapshotWriter::writeCollections() const {
  writeFileAtomic(particleCollectionPath(), xdmfParticleCollection(snapshots_, options_.fields));
  writeFileAtomic(contactCollectionPath(),
                  xdmfContactCollection(snapshots_, options_.contact_fields));
}

}  // namespace polydem::io

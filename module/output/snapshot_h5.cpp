#include "polydem/output/snapshot_h5.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <utility>

#include "polydem/core/error.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/hdf5/hdf5_file.h"
#include "polydem/output/output_file.h"
#include "polydem/setup/snapshot_fields.h"

namespace polydem::output {

namespace {

using hdf5::Dataset;
using hdf5::File;
using hdf5::Info;
using hdf5::Slice;

/// Where this rank's rows of a table go: `runs` of the file's `total` rows, in file order.
struct Placement {
  std::uint64_t total = 0;
  std::vector<Dataset::Run> runs;
};

Placement contiguous(const Slice& s) {
  return {s.total, {{s.offset, s.rows}}};
}

/// Creates a dataset and writes this rank's rows in one collective call; kept in `open` until
/// File::finish() stores the checksums.
template <typename T>
void put(File& file, std::vector<Dataset>& open, const std::string& name, const Placement& where,
         std::size_t cols, const std::vector<T>& data, const Info& info) {
  Dataset d = file.create<T>(name, where.total, cols, info);
  d.writeRuns(data.data(), where.runs);
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
void putParticleField(File& file, std::vector<Dataset>& open, const setup::SnapshotField& f,
                      const Placement& faces, const PolyhedraBatch& b, int rank) {
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
  } else if (name == "joint") {  // the face's own value, not its particle's
    put(file, open, dataset, faces, cols, b.face_joint, info);
  } else if (name == "pressure") {  // the face's own value too
    put(file, open, dataset, faces, cols, b.face_pressure, info);
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

void putContactField(File& file, std::vector<Dataset>& open, const setup::SnapshotField& f,
                     const Placement& contacts, const ContactBatch& c, int rank) {
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
  } else if (name == "joint") {
    put(file, open, dataset, contacts, cols,
        perContact<std::int32_t>(c,
                                 [](R r, std::vector<std::int32_t>& o) { o.push_back(r.joint); }),
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

/// `b` with its particles in uid order.
PolyhedraBatch byUid(const PolyhedraBatch& b) {
  std::vector<std::size_t> order(b.particles.size());
  for (std::size_t p = 0; p < order.size(); ++p) order[p] = p;
  std::sort(order.begin(), order.end(),
            [&](std::size_t x, std::size_t y) { return b.particles[x].uid < b.particles[y].uid; });
  PolyhedraBatch out;
  std::vector<int> face;
  for (const std::size_t p : order) {
    const std::int64_t first_point = p > 0 ? b.point_end[p - 1] : 0;
    const std::int64_t first_face = p > 0 ? b.particle_face_end[p - 1] : 0;
    out.addParticle(b.particles[p],
                    std::span<const Vec3>(b.points.data() + first_point,
                                          static_cast<std::size_t>(b.point_end[p] - first_point)));
    for (std::int64_t f = first_face; f < b.particle_face_end[p]; ++f) {
      face.clear();
      for (std::int64_t i = f > 0 ? b.face_end[f - 1] : 0; i < b.face_end[f]; ++i) {
        face.push_back(static_cast<int>(b.connectivity[i] - first_point));
      }
      out.addFace(face, b.face_joint[static_cast<std::size_t>(f)],
                  b.face_pressure[static_cast<std::size_t>(f)]);
    }
  }
  return out;
}

/// The rows of one particle in the particle, point, face and topology tables.
struct ParticleRows {
  std::uint64_t uid = 0;
  std::array<std::uint64_t, 4> count{};
};
enum ParticleTable { kParticleRow, kPointRow, kFaceRow, kTopologyRow };

/// Places the rows of the particles of `b` (in uid order) in tables of all ranks' particles in
/// uid order, whatever rank holds them: gathers every particle's row counts (O(particles) per
/// rank and snapshot) and sums them up in uid order. Collective.
std::array<Placement, 4> uidPlacements(const PolyhedraBatch& b, MPI_Comm comm) {
  std::vector<ParticleRows> mine(b.particles.size());
  for (std::size_t p = 0; p < mine.size(); ++p) {
    const std::int64_t first_face = p > 0 ? b.particle_face_end[p - 1] : 0;
    const std::int64_t faces = b.particle_face_end[p] - first_face;
    const std::int64_t first_index = first_face > 0 ? b.face_end[first_face - 1] : 0;
    const std::int64_t indices =
        (faces > 0 ? b.face_end[b.particle_face_end[p] - 1] : first_index) - first_index;
    mine[p].uid = b.particles[p].uid;
    mine[p].count = {
        1, static_cast<std::uint64_t>(b.point_end[p] - (p > 0 ? b.point_end[p - 1] : 0)),
        static_cast<std::uint64_t>(faces), static_cast<std::uint64_t>(2 * faces + indices)};
  }
  auto all = mpi::allgatherv(mine, comm);
  std::sort(all.begin(), all.end(),
            [](const ParticleRows& x, const ParticleRows& y) { return x.uid < y.uid; });
  std::array<Placement, 4> out;
  std::array<std::uint64_t, 4> row{};
  std::size_t next = 0;  // the next of `mine` (uid order) in `all`
  for (const ParticleRows& r : all) {
    if (next < mine.size() && mine[next].uid == r.uid) {
      for (int t = 0; t < 4; ++t) {
        auto& runs = out[t].runs;
        if (!runs.empty() && runs.back().first + runs.back().rows == row[t]) {
          runs.back().rows += r.count[t];  // continues the previous run
        } else {
          runs.push_back({row[t], r.count[t]});
        }
      }
      ++next;
    }
    for (int t = 0; t < 4; ++t) row[t] += r.count[t];
  }
  for (int t = 0; t < 4; ++t) out[t].total = row[t];
  return out;
}

std::string joined(const std::vector<std::string>& names) {
  return join(names, ",");
}

}  // namespace

XdmfSnapshotWriter::XdmfSnapshotWriter(std::string dir, MPI_Comm comm, Options options)
    : dir_(std::move(dir)), comm_(comm), options_(std::move(options)) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
  if (options_.fields.empty()) options_.fields = setup::kDefaultParticleFields;
  if (options_.contact_fields.empty()) options_.contact_fields = setup::kDefaultContactFields;
  for (const auto& f : options_.fields) {
    if (auto problem = setup::unknownField(setup::kParticleFields, f); !problem.empty())
      throw Error(problem);
  }
  for (const auto& f : options_.contact_fields) {
    if (auto problem = setup::unknownField(setup::kContactFields, f); !problem.empty())
      throw Error(problem);
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

void XdmfSnapshotWriter::writeFile(const std::string& path, const std::string& tmp,
                                   std::int64_t step, double time, const PolyhedraBatch& unsorted,
                                   const ContactBatch& c, XdmfSnapshot& counts) const {
  // Particles, points, faces and topology in uid order, so that these tables are the same on any
  // rank count; the contacts in rank order.
  const PolyhedraBatch b = byUid(unsorted);
  const auto place = uidPlacements(b, comm_);
  const Slice s = hdf5::writerSlice(c.contacts.size(), comm_);
  const Placement& faces = place[kFaceRow];
  counts.points = place[kPointRow].total;
  counts.faces = faces.total;
  counts.topology = place[kTopologyRow].total;
  counts.contacts = s.total;

  // Mixed topology: each face is (3 = polygon, vertex count, vertex indices), the indices made
  // global: the particle's first row in /mesh/points plus the vertex's index in the particle.
  std::vector<std::int64_t> topology;
  std::size_t run = 0;
  std::uint64_t in_run = 0;  // points of the current run already passed
  for (std::size_t p = 0; p < b.particles.size(); ++p) {
    const auto& point_runs = place[kPointRow].runs;
    const std::int64_t first_point = p > 0 ? b.point_end[p - 1] : 0;
    const std::int64_t points = b.point_end[p] - first_point;
    while (in_run >= point_runs[run].rows) {
      ++run;
      in_run = 0;
    }
    const auto global = static_cast<std::int64_t>(point_runs[run].first + in_run);
    in_run += static_cast<std::uint64_t>(points);
    for (std::int64_t f = p > 0 ? b.particle_face_end[p - 1] : 0; f < b.particle_face_end[p]; ++f) {
      const std::int64_t begin = f > 0 ? b.face_end[f - 1] : 0;
      topology.insert(topology.end(), {3, b.face_end[f] - begin});
      for (std::int64_t i = begin; i < b.face_end[f]; ++i) {
        topology.push_back(global + b.connectivity[i] - first_point);
      }
    }
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
    vertex.push_back(static_cast<std::int64_t>(s.offset + i));
  }
  const Placement contacts = contiguous(s);

  hdf5::CheckpointIoOptions io;
  io.kind = "snapshot";
  io.sync_on_close = false;
  const hdf5::ErrorSilencer quiet;  // HDF5's errors become exceptions, not printed stacks
  File file = File::create(tmp, comm_, io, path);
  std::vector<Dataset> open;
  file.createGroup("/mesh", "the faces of all blocks as polygons (XDMF Mixed topology)");
  put(file, open, "/mesh/points", place[kPointRow], 3, points, {"m", "vertices, world frame"});
  put(file, open, "/mesh/topology", place[kTopologyRow], 1, topology,
      {"", "per face: 3 (polygon), vertex count, indices into /mesh/points"});
  file.createGroup("/particles", "one row per particle");
  const Placement& particles = place[kParticleRow];
  put(file, open, "/particles/uid", particles, 1, uid, {"", "particle uid"});
  put(file, open, "/particles/face_count", particles, 1, face_count,
      {"", "faces of the particle: its rows in /faces follow those of the previous rows"});
  put(file, open, "/particles/position", particles, 3, position, {"m", "centroid"});
  put(file, open, "/particles/velocity", particles, 3, velocity, {"m/s", "centroid velocity"});
  file.createGroup("/faces", "the chosen particle fields, one row per face (cell data)");
  for (const auto& name : options_.fields) {
    putParticleField(file, open, *setup::findField(setup::kParticleFields, name), faces, b, rank_);
  }
  file.createGroup("/contacts", "touching contacts: one row per contact point");
  put(file, open, "/contacts/point", contacts, 3, contact_points, {"m", "contact point"});
  put(file, open, "/contacts/vertex", contacts, 1, vertex, {"", "row index (vertex cells)"});
  for (const auto& name : options_.contact_fields) {
    putContactField(file, open, *setup::findField(setup::kContactFields, name), contacts, c, rank_);
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
  file.writeAttribute("/", "joint_names", join(options_.joint_names, "\n"));
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
    writeFile(path, tmp, step, time, particles, *contacts, counts);  // throws on every rank alike
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

}  // namespace polydem::output

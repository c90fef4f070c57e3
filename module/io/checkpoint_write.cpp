// writeCheckpoint: validation, the temporary file, the datasets, the atomic rename.
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <cstring>
#include <system_error>

#include "core/error.h"
#include "core/mpi_env.h"
#include "core/strings.h"
#include "io/checkpoint.h"
#include "io/checkpoint_checksum.h"
#include "io/checkpoint_layout.h"
#include "io/hdf5_file.h"

namespace polydem::io {

namespace {

namespace fs = std::filesystem;
using particles::Particle;

h5::Info info(const layout::Dataset& d) {
  return {d.units, d.description};
}

/// Problems with the caller's data on this rank (checked before any file is touched).
std::optional<std::string> invalidData(const CheckpointData& data, int rank) {
  const auto shapes = static_cast<std::int32_t>(data.shapes.size());
  const auto materials = static_cast<std::int32_t>(data.materials.size());
  for (const Particle& p : data.particles) {
    if (p.isGhost()) return cat("particle uid ", p.uid, " is a ghost copy; pass owned ones only");
    if (p.shape < 0 || p.shape >= shapes) {
      return cat("particle uid ", p.uid, " has shape ", p.shape, " but the table has ", shapes);
    }
    if (p.material < 0 || p.material >= materials) {
      return cat("particle uid ", p.uid, " has material ", p.material, " but the table has ",
                 materials);
    }
  }
  if (data.pair_keys.size() != data.pair_histories.size()) {
    return cat(data.pair_keys.size(), " pair keys but ", data.pair_histories.size(), " histories");
  }
  for (const auto& k : data.pair_keys) {
    if (!(k.lo < k.hi)) return cat("pair (", k.lo, ", ", k.hi, ") is not ordered lo < hi");
  }
  if (rank != 0) return std::nullopt;  // the replicated part is written from rank 0's copy
  const auto& d = data.domain;
  const std::int64_t blocks = std::int64_t{d.blocks[0]} * d.blocks[1] * d.blocks[2];
  if (d.blocks[0] < 1 || d.blocks[1] < 1 || d.blocks[2] < 1 ||
      static_cast<std::int64_t>(d.rank_map.size()) != blocks) {
    return cat("the rank map has ", d.rank_map.size(), " entries for ", blocks, " blocks");
  }
  for (const auto& s : data.shapes) {
    for (const auto& face : s.faces) {
      for (int v : face) {
        if (v < 0 || v >= static_cast<int>(s.vertices.size())) {
          return cat("shape '", s.name, "' has a face with vertex ", v, " of ", s.vertices.size());
        }
      }
    }
  }
  for (const auto& in : data.interactions) {
    if (in.a < 0 || in.a >= materials || in.b < 0 || in.b >= materials) {
      return cat("interaction (", in.a, ", ", in.b, ") names a material out of range");
    }
  }
  const double exact = ExactSum::fromDigits(data.time_digits).value();
  if (std::memcmp(&exact, &data.time, sizeof exact) != 0) {
    return cat("time ", data.time, " is not the rounded exact time ", exact,
               " (pass TimeLoop::exactTime().digits())");
  }
  return std::nullopt;
}

/// Broadcasts rank 0's value: attributes must be written with identical values on every rank.
template <typename T>
T fromRankZero(T value, MPI_Comm comm) {
  MPI_Bcast(&value, sizeof value, MPI_BYTE, 0, comm);
  return value;
}

std::string fromRankZero(std::string text, MPI_Comm comm) {
  auto length = fromRankZero<std::uint64_t>(text.size(), comm);
  text.resize(length);
  MPI_Bcast(text.data(), static_cast<int>(length), MPI_CHAR, 0, comm);
  return text;
}

class Writer {
 public:
  Writer(h5::File& file, const CheckpointData& data)
      : f_(file), data_(data), comm_(file.comm()), rank_(mpi::rank(comm_)) {}

  void run() {
    writeRoot();
    writeRun();
    writeShapes();
    writeMaterials();
    writeDomain();
    writeParticles();
    writeContacts();
  }

 private:
  /// A replicated table: rank 0 writes all `rows`, the others none.
  template <typename T>
  void table(const layout::Dataset& d, const std::vector<T>& values, std::size_t cols) {
    const std::uint64_t rows = rank_ == 0 ? values.size() / cols : 0;
    f_.write<T>(d.name, rank_ == 0 ? std::span<const T>(values) : std::span<const T>(), cols,
                h5::writerSlice(rows, comm_), info(d));
  }

  void writeRoot() {
    f_.writeAttribute("/", "format", std::string(layout::kFormatName));
    f_.writeAttribute<std::int32_t>("/", "format_version", kCheckpointFormatVersion);
    f_.writeAttribute("/", "code_version", fromRankZero(data_.code_version, comm_));
    f_.writeAttribute<std::int32_t>("/", "writer_ranks", mpi::size(comm_));
    f_.writeAttribute("/", "checksum_algorithm", std::string(layout::kChecksumAlgorithm));
  }

  void writeRun() {
    f_.createGroup("/run", "step, time and stage of the run");
    f_.writeAttribute("/run", "step", fromRankZero(data_.step, comm_));
    f_.writeAttribute("/run", "time", fromRankZero(data_.time, comm_));
    f_.writeAttribute("/run", "dt", fromRankZero(data_.dt, comm_));
    const auto digits = fromRankZero(data_.time_digits, comm_);
    f_.writeAttribute("/run", "time_digits", std::span<const std::int64_t>(digits));
    const auto stage = fromRankZero(data_.stage, comm_);
    f_.writeAttribute("/run", "stage", static_cast<std::int32_t>(stage));
    f_.writeAttribute("/run", "stage_name", std::string(toString(stage)));
    f_.writeAttribute("/run", "equilibrium_steps", fromRankZero(data_.equilibrium_steps, comm_));
    f_.writeAttribute<std::uint8_t>("/run", "equilibrium_reached",
                                    fromRankZero<std::uint8_t>(data_.equilibrium_reached, comm_));
    f_.writeText(layout::kRunState.name, data_.run_state, info(layout::kRunState));

    f_.createGroup("/scene", "the scene file the run was started from");
    f_.writeText(layout::kSceneToml.name, data_.scene_toml, info(layout::kSceneToml));
    f_.writeAttribute("/scene", "file_name", fromRankZero(data_.scene_file, comm_));
    f_.writeAttribute("/scene", "hash", fromRankZero(checksumOfBytes(data_.scene_toml), comm_));
  }

  void writeShapes() {
    f_.createGroup("/shapes", "shape table, body frame (centroid at the origin, principal axes)");
    std::vector<std::string> names;
    std::vector<std::int64_t> vertex_offset{0}, face_offset{0}, face_vertex_offset{0};
    std::vector<double> vertices, volume, moments, circumradius, inradius;
    std::vector<std::int32_t> face_vertices;
    for (const auto& s : data_.shapes) {
      names.push_back(s.name);
      for (const Vec3& v : s.vertices) vertices.insert(vertices.end(), {v.x(), v.y(), v.z()});
      vertex_offset.push_back(vertex_offset.back() + static_cast<std::int64_t>(s.vertices.size()));
      for (const auto& face : s.faces) {
        face_vertices.insert(face_vertices.end(), face.begin(), face.end());
        face_vertex_offset.push_back(static_cast<std::int64_t>(face_vertices.size()));
      }
      face_offset.push_back(face_offset.back() + static_cast<std::int64_t>(s.faces.size()));
      volume.push_back(s.volume);
      moments.insert(moments.end(),
                     {s.principal_moments.x(), s.principal_moments.y(), s.principal_moments.z()});
      circumradius.push_back(s.circumradius);
      inradius.push_back(s.inradius);
    }
    f_.writeStrings(layout::kShapeName.name, names, info(layout::kShapeName));
    table(layout::kShapeVertexOffset, vertex_offset, 1);
    table(layout::kShapeVertices, vertices, 3);
    table(layout::kShapeFaceOffset, face_offset, 1);
    table(layout::kFaceVertexOffset, face_vertex_offset, 1);
    table(layout::kFaceVertices, face_vertices, 1);
    table(layout::kShapeVolume, volume, 1);
    table(layout::kShapeMoments, moments, 3);
    table(layout::kShapeCircumradius, circumradius, 1);
    table(layout::kShapeInradius, inradius, 1);
  }

  template <typename Getter>
  std::vector<double> column(const auto& items, Getter get) {
    std::vector<double> out;
    for (const auto& item : items) out.push_back(get(item));
    return out;
  }

  void writeMaterials() {
    using particles::Material;
    f_.createGroup("/materials", "material table (rows are /particles/material)");
    const auto& m = data_.materials;
    std::vector<std::string> names;
    for (const auto& x : m) names.push_back(x.name);
    f_.writeStrings(layout::kMaterialName.name, names, info(layout::kMaterialName));
    table(layout::kMaterialDensity, column(m, [](const Material& x) { return x.density; }), 1);
    table(layout::kMaterialKn, column(m, [](const Material& x) { return x.kn; }), 1);
    table(layout::kMaterialKs, column(m, [](const Material& x) { return x.ks; }), 1);
    table(layout::kMaterialFriction, column(m, [](const Material& x) { return x.friction_angle; }),
          1);
    table(layout::kMaterialCohesion, column(m, [](const Material& x) { return x.cohesion; }), 1);
    table(layout::kMaterialNormalDamping,
          column(m, [](const Material& x) { return x.normal_damping; }), 1);
    table(layout::kMaterialLocalDamping,
          column(m, [](const Material& x) { return x.local_damping; }), 1);
    table(layout::kMaterialPenalty, column(m, [](const Material& x) { return x.penalty; }), 1);

    using In = Scene::Interaction;
    f_.createGroup("/materials/interaction", "explicit contact properties of material pairs");
    const auto& in = data_.interactions;
    std::vector<std::int32_t> pairs;
    for (const auto& x : in) pairs.insert(pairs.end(), {x.a, x.b});
    table(layout::kInteractionPair, pairs, 2);
    table(layout::kInteractionKn, column(in, [](const In& x) { return x.properties.kn; }), 1);
    table(layout::kInteractionKs, column(in, [](const In& x) { return x.properties.ks; }), 1);
    table(layout::kInteractionFriction,
          column(in, [](const In& x) { return x.properties.friction_angle; }), 1);
    table(layout::kInteractionCohesion,
          column(in, [](const In& x) { return x.properties.cohesion; }), 1);
    table(layout::kInteractionNormalDamping,
          column(in, [](const In& x) { return x.properties.normal_damping; }), 1);
    table(layout::kInteractionPenalty, column(in, [](const In& x) { return x.properties.penalty; }),
          1);
  }

  void writeDomain() {
    const auto& d = data_.domain;
    f_.createGroup("/domain", "block forest of the writer (domain/block_forest.h)");
    table(layout::kDomainLo, std::vector<double>{d.lo.x(), d.lo.y(), d.lo.z()}, 1);
    table(layout::kDomainHi, std::vector<double>{d.hi.x(), d.hi.y(), d.hi.z()}, 1);
    table(layout::kDomainBlocks, std::vector<std::int32_t>(d.blocks.begin(), d.blocks.end()), 1);
    std::vector<std::uint8_t> periodic;
    for (bool p : d.periodic) periodic.push_back(p ? 1 : 0);
    table(layout::kDomainPeriodic, periodic, 1);
    table(layout::kDomainRankMap, std::vector<std::int32_t>(d.rank_map.begin(), d.rank_map.end()),
          1);
    f_.writeAttribute<std::int32_t>("/domain", "ranks", fromRankZero(d.ranks, comm_));
  }

  /// Packs one field of `rows` rows into a contiguous buffer (fill(i, out) writes row i's `cols`
  /// values) and writes it.
  template <typename T, typename Fill>
  void field(const layout::Dataset& d, std::size_t rows, std::size_t cols, const h5::Slice& slice,
             std::vector<T>& buffer, Fill fill) {
    buffer.resize(rows * cols);
    for (std::size_t i = 0; i < rows; ++i) fill(i, buffer.data() + i * cols);
    f_.write<T>(d.name, buffer, cols, slice, info(d));
  }

  static void put(const Vec3& v, double* out) {
    out[0] = v.x();
    out[1] = v.y();
    out[2] = v.z();
  }

  void writeParticles() {
    f_.createGroup("/particles",
                   "particles: replicated (fixed, driven) rows first, then free ones");
    // Rank 0 writes the replicated particles first, so that they are rows [0, G) of the file.
    std::vector<const Particle*> rows;
    if (rank_ == 0) {
      for (const auto& p : data_.particles) {
        if (p.isGlobal()) rows.push_back(&p);
      }
    }
    const auto replicated = fromRankZero<std::uint64_t>(rows.size(), comm_);
    for (const auto& p : data_.particles) {
      if (!p.isGlobal()) rows.push_back(&p);
    }
    f_.writeAttribute<std::uint64_t>("/particles", "replicated_count", replicated);
    const std::size_t n = rows.size();
    const h5::Slice slice = h5::writerSlice(n, comm_);
    field(layout::kUid, n, 1, slice, u64_, [&](std::size_t i, auto* o) { *o = rows[i]->uid; });
    field(layout::kShape, n, 1, slice, i32_, [&](std::size_t i, auto* o) { *o = rows[i]->shape; });
    field(layout::kMaterial, n, 1, slice, i32_,
          [&](std::size_t i, auto* o) { *o = rows[i]->material; });
    field(layout::kFlags, n, 1, slice, u32_, [&](std::size_t i, auto* o) { *o = rows[i]->flags; });
    field(layout::kDriver, n, 1, slice, i32_,
          [&](std::size_t i, auto* o) { *o = rows[i]->driver; });
    field(layout::kPosition, n, 3, slice, f64_,
          [&](std::size_t i, double* o) { put(rows[i]->position, o); });
    field(layout::kOrientation, n, 4, slice, f64_, [&](std::size_t i, double* o) {
      const Quat& q = rows[i]->orientation;
      o[0] = q.w();
      o[1] = q.x();
      o[2] = q.y();
      o[3] = q.z();
    });
    field(layout::kVelocity, n, 3, slice, f64_,
          [&](std::size_t i, double* o) { put(rows[i]->velocity, o); });
    field(layout::kAngularMomentum, n, 3, slice, f64_,
          [&](std::size_t i, double* o) { put(rows[i]->angular_momentum, o); });
  }

  void writeContacts() {
    f_.createGroup("/contacts", "pair histories, one row per pair");
    const auto& keys = data_.pair_keys;
    const auto& h = data_.pair_histories;
    const std::size_t n = h.size();
    const h5::Slice slice = h5::writerSlice(n, comm_);
    field(layout::kPair, n, 2, slice, u64_, [&](std::size_t i, std::uint64_t* o) {
      o[0] = keys[i].lo;
      o[1] = keys[i].hi;
    });
    field(layout::kShearForce, n, 3, slice, f64_,
          [&](std::size_t i, double* o) { put(h[i].shear_force, o); });
    field(layout::kNormal, n, 3, slice, f64_,
          [&](std::size_t i, double* o) { put(h[i].normal, o); });
    field(layout::kWarmDirection, n, 3, slice, f64_,
          [&](std::size_t i, double* o) { put(h[i].kernel.warm_direction, o); });
    field(layout::kWarmPoint, n, 3, slice, f64_,
          [&](std::size_t i, double* o) { put(h[i].kernel.warm_point, o); });
    field(layout::kWarmValid, n, 1, slice, u32_,
          [&](std::size_t i, auto* o) { *o = h[i].kernel.warm_valid; });
    field(layout::kKernelReserved, n, 1, slice, u32_,
          [&](std::size_t i, auto* o) { *o = h[i].kernel.reserved; });
    field(layout::kTouching, n, 1, slice, u32_,
          [&](std::size_t i, auto* o) { *o = h[i].touching; });
  }

  h5::File& f_;
  const CheckpointData& data_;
  MPI_Comm comm_;
  int rank_;
  // Packing buffers, reused from field to field.
  std::vector<double> f64_;
  std::vector<std::uint64_t> u64_;
  std::vector<std::uint32_t> u32_;
  std::vector<std::int32_t> i32_;
};

/// Bytes the file will take, about: every dataset's payload (the replicated tables are small) and
/// room for HDF5's metadata. Collective.
std::uint64_t estimatedBytes(const CheckpointData& data, MPI_Comm comm) {
  constexpr std::uint64_t kParticleBytes = 8 + 4 * 4 + 13 * 8;  // uid, 4 ints, 13 doubles
  constexpr std::uint64_t kPairBytes = 2 * 8 + 12 * 8 + 3 * 4;  // pair, 4 vectors, 3 words
  std::uint64_t mine = data.particles.size() * kParticleBytes + data.pair_keys.size() * kPairBytes;
  if (mpi::rank(comm) == 0) {
    mine += data.scene_toml.size() + data.run_state.size();
    for (const auto& s : data.shapes) mine += 48 * s.vertices.size() + 64 * s.faces.size() + 256;
  }
  std::uint64_t total = 0;
  MPI_Allreduce(&mine, &total, 1, MPI_UINT64_T, MPI_SUM, comm);
  return total + (std::uint64_t{1} << 20);
}

/// A write that cannot fit is refused before it starts: HDF5 cannot close a parallel file cleanly
/// once its metadata flush failed (disk full, file size limit), and may then hang or crash.
std::optional<std::string> noRoomFor(std::uint64_t bytes, const fs::path& path, int rank) {
  rlimit limit{};
  if (getrlimit(RLIMIT_FSIZE, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY &&
      bytes > limit.rlim_cur) {
    return cat("needs about ", bytes, " bytes, above the file size limit of ", limit.rlim_cur,
               " bytes (ulimit -f) of rank ", rank);
  }
  struct statvfs fs_info {};
  const fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  if (rank == 0 && statvfs(dir.c_str(), &fs_info) == 0) {
    const std::uint64_t available = std::uint64_t{fs_info.f_bavail} * fs_info.f_frsize;
    if (bytes > available) {
      return cat("needs about ", bytes, " bytes but only ", available, " are free in ",
                 dir.string());
    }
  }
  return std::nullopt;
}

/// Makes a rename durable: fsync of the directory that holds the entry.
void syncDirectory(const fs::path& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

}  // namespace

const char* toString(CheckpointStage stage) {
  return stage == CheckpointStage::kEquilibrium ? "equilibrium" : "main";
}

void writeCheckpoint(const fs::path& path, const CheckpointData& data, MPI_Comm comm,
                     const CheckpointIoOptions& options) {
  const h5::ErrorSilencer silence;
  const int rank = mpi::rank(comm);
  std::optional<std::string> problem = invalidData(data, rank);
  if (problem) problem = "checkpoint " + path.string() + ": " + *problem;
  h5::agree(problem, comm);
  problem = noRoomFor(estimatedBytes(data, comm), path, rank);
  if (problem) problem = "checkpoint " + path.string() + ": " + *problem;
  h5::agree(problem, comm);
  const auto pid = fromRankZero<std::int64_t>(::getpid(), comm);
  const fs::path temporary = path.string() + ".tmp." + std::to_string(pid);

  std::optional<std::string> failure;
  try {
    h5::File file = h5::File::create(temporary, comm, options);
    Writer(file, data).run();
    file.close();  // H5Fflush (MPI_File_sync) and H5Fclose
  } catch (const CheckpointError& e) {
    failure = e.what();  // agreed: every rank is here, and the file is closed on every rank
  }
  MPI_Barrier(comm);
  if (rank == 0) {
    std::error_code ec;
    if (!failure) {
      fs::rename(temporary, path, ec);  // atomic on POSIX: readers see the old or the new file
      if (ec) {
        failure = "checkpoint " + path.string() + ": cannot rename " + temporary.string() +
                  " to it: " + ec.message();
      } else {
        syncDirectory(path.parent_path());
      }
    }
    if (failure) fs::remove(temporary, ec);
  }
  h5::agree(rank == 0 ? failure : std::nullopt, comm);
}

}  // namespace polydem::io

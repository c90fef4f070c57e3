// readCheckpoint: every dataset read, its type, shape and checksum verified, and the contents
// checked for consistency (offsets, index ranges, the replicated rows, the exact time).
#include <cstring>

#include "core/error.h"
#include "core/mpi_env.h"
#include "core/strings.h"
#include "io/checkpoint.h"
#include "io/checkpoint_checksum.h"
#include "io/checkpoint_layout.h"
#include "io/checkpoint_read_all.h"
#include "io/hdf5_file.h"

namespace polydem::io {

namespace {

using particles::Particle;

bool sameBits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

Vec3 vec3At(const std::vector<double>& v, std::size_t row) {
  return {v[3 * row], v[3 * row + 1], v[3 * row + 2]};
}

class Reader {
 public:
  explicit Reader(h5::File& file) : f_(file), comm_(file.comm()) {}

  CheckpointData run() {
    readRoot();
    readRun();
    readShapes();
    readMaterials();
    readDomain();
    readParticles();
    readContacts();
    return std::move(d_);
  }

 private:
  /// Thrown where every rank finds the same problem (replicated data); distributed problems go
  /// through h5::agree.
  CheckpointError inconsistent(const std::string& what) const {
    return CheckpointError(f_.context(what));
  }

  std::uint64_t rows(const layout::Dataset& d) const {
    const auto dims = f_.dims(d.name);
    if (dims.empty()) throw inconsistent(cat("dataset ", d.name, " is a scalar"));
    return dims[0];
  }

  template <typename T>
  std::vector<T> table(const layout::Dataset& d, std::uint64_t n, std::size_t cols = 1) {
    return f_.read<T>(d.name, cols, h5::wholeSlice(n));
  }

  /// Offsets must start at 0, never decrease and end at `end` (the row count of what they index).
  void checkOffsets(const layout::Dataset& d, const std::vector<std::int64_t>& offsets,
                    std::uint64_t end, const char* indexed) const {
    bool ok = !offsets.empty() && offsets.front() == 0 &&
              static_cast<std::uint64_t>(offsets.back()) == end;
    for (std::size_t i = 1; ok && i < offsets.size(); ++i) ok = offsets[i - 1] <= offsets[i];
    if (!ok) {
      throw inconsistent(cat("dataset ", d.name, " is not a list of offsets from 0 to ", end,
                             " (the rows of ", indexed, "): inconsistent sizes"));
    }
  }

  void readRoot() {
    const std::string format = f_.readStringAttribute("/", "format");
    if (format != layout::kFormatName) {
      throw inconsistent("not a polydem checkpoint (attribute format is '" + format + "')");
    }
    d_.format_version = f_.readAttribute<std::int32_t>("/", "format_version");
    if (d_.format_version != kCheckpointFormatVersion) {
      throw inconsistent(cat("format version ", d_.format_version, "; this polydem reads version ",
                             kCheckpointFormatVersion));
    }
    d_.code_version = f_.readStringAttribute("/", "code_version");
    d_.writer_ranks = f_.readAttribute<std::int32_t>("/", "writer_ranks");
  }

  void readRun() {
    d_.step = f_.readAttribute<std::int64_t>("/run", "step");
    d_.time = f_.readAttribute<double>("/run", "time");
    d_.dt = f_.readAttribute<double>("/run", "dt");
    const auto digits = f_.readAttribute<std::int64_t>("/run", "time_digits", ExactSum::kDigits);
    std::copy(digits.begin(), digits.end(), d_.time_digits.begin());
    const auto stage = f_.readAttribute<std::int32_t>("/run", "stage");
    if (stage != 0 && stage != 1) throw inconsistent(cat("/run: stage ", stage, " is not 0 or 1"));
    d_.stage = static_cast<CheckpointStage>(stage);
    d_.equilibrium_steps = f_.readAttribute<std::int64_t>("/run", "equilibrium_steps");
    d_.equilibrium_reached = f_.readAttribute<std::uint8_t>("/run", "equilibrium_reached") != 0;
    const double exact = ExactSum::fromDigits(d_.time_digits).value();
    if (!sameBits(exact, d_.time)) {
      throw inconsistent(cat("/run: time ", d_.time, " is not the rounded time_digits ", exact));
    }
    d_.run_state = f_.readText(layout::kRunState.name);

    d_.scene_toml = f_.readText(layout::kSceneToml.name);
    d_.scene_file = f_.readStringAttribute("/scene", "file_name");
    d_.scene_hash = f_.readAttribute<std::uint64_t>("/scene", "hash");
    if (checksumOfBytes(d_.scene_toml) != d_.scene_hash) {
      throw inconsistent("/scene: the scene text does not match its hash");
    }
  }

  void readShapes() {
    const std::uint64_t n = rows(layout::kShapeName);
    const auto names = f_.readStrings(layout::kShapeName.name, n);
    const auto vertex_offset = table<std::int64_t>(layout::kShapeVertexOffset, n + 1);
    const std::uint64_t n_vertices = rows(layout::kShapeVertices);
    checkOffsets(layout::kShapeVertexOffset, vertex_offset, n_vertices, "/shapes/vertices");
    const auto vertices = table<double>(layout::kShapeVertices, n_vertices, 3);
    const auto face_offset = table<std::int64_t>(layout::kShapeFaceOffset, n + 1);
    const std::uint64_t face_rows = rows(layout::kFaceVertexOffset);
    if (face_rows == 0) throw inconsistent(cat(layout::kFaceVertexOffset.name, " is empty"));
    const std::uint64_t n_faces = face_rows - 1;
    checkOffsets(layout::kShapeFaceOffset, face_offset, n_faces, "the faces");
    const auto face_vertex_offset = table<std::int64_t>(layout::kFaceVertexOffset, n_faces + 1);
    const std::uint64_t n_indices = rows(layout::kFaceVertices);
    checkOffsets(layout::kFaceVertexOffset, face_vertex_offset, n_indices, "/shapes/face_vertices");
    const auto face_vertices = table<std::int32_t>(layout::kFaceVertices, n_indices);
    const auto volume = table<double>(layout::kShapeVolume, n);
    const auto moments = table<double>(layout::kShapeMoments, n, 3);
    const auto circumradius = table<double>(layout::kShapeCircumradius, n);
    const auto inradius = table<double>(layout::kShapeInradius, n);

    for (std::uint64_t s = 0; s < n; ++s) {
      CheckpointShape shape;
      shape.name = names[s];
      const auto v0 = static_cast<std::size_t>(vertex_offset[s]);
      const auto v1 = static_cast<std::size_t>(vertex_offset[s + 1]);
      for (std::size_t v = v0; v < v1; ++v) shape.vertices.push_back(vec3At(vertices, v));
      for (auto f = face_offset[s]; f < face_offset[s + 1]; ++f) {
        const auto begin = face_vertices.begin() + face_vertex_offset[f];
        const auto end = face_vertices.begin() + face_vertex_offset[f + 1];
        shape.faces.emplace_back(begin, end);
        for (int v : shape.faces.back()) {
          if (v < 0 || static_cast<std::size_t>(v) >= v1 - v0) {
            throw inconsistent(cat("/shapes/face_vertices: shape '", shape.name,
                                   "' has a face with vertex ", v, " of ", v1 - v0));
          }
        }
      }
      shape.volume = volume[s];
      shape.principal_moments = vec3At(moments, s);
      shape.circumradius = circumradius[s];
      shape.inradius = inradius[s];
      d_.shapes.push_back(std::move(shape));
    }
  }

  void readMaterials() {
    const std::uint64_t n = rows(layout::kMaterialName);
    const auto names = f_.readStrings(layout::kMaterialName.name, n);
    const auto density = table<double>(layout::kMaterialDensity, n);
    const auto kn = table<double>(layout::kMaterialKn, n);
    const auto ks = table<double>(layout::kMaterialKs, n);
    const auto friction = table<double>(layout::kMaterialFriction, n);
    const auto cohesion = table<double>(layout::kMaterialCohesion, n);
    const auto normal_damping = table<double>(layout::kMaterialNormalDamping, n);
    const auto local_damping = table<double>(layout::kMaterialLocalDamping, n);
    const auto penalty = table<double>(layout::kMaterialPenalty, n);
    for (std::uint64_t i = 0; i < n; ++i) {
      d_.materials.push_back({names[i], density[i], kn[i], ks[i], friction[i], cohesion[i],
                              normal_damping[i], local_damping[i], penalty[i]});
    }
    const std::uint64_t k = rows(layout::kInteractionPair);
    const auto pairs = table<std::int32_t>(layout::kInteractionPair, k, 2);
    const auto ikn = table<double>(layout::kInteractionKn, k);
    const auto iks = table<double>(layout::kInteractionKs, k);
    const auto ifriction = table<double>(layout::kInteractionFriction, k);
    const auto icohesion = table<double>(layout::kInteractionCohesion, k);
    const auto idamping = table<double>(layout::kInteractionNormalDamping, k);
    const auto ipenalty = table<double>(layout::kInteractionPenalty, k);
    for (std::uint64_t i = 0; i < k; ++i) {
      Scene::Interaction in;
      in.a = pairs[2 * i];
      in.b = pairs[2 * i + 1];
      if (in.a < 0 || static_cast<std::uint64_t>(in.a) >= n || in.b < 0 ||
          static_cast<std::uint64_t>(in.b) >= n) {
        throw inconsistent(cat(layout::kInteractionPair.name, ": row ", i, " names material (",
                               in.a, ", ", in.b, ") of ", n));
      }
      in.properties = {ikn[i], iks[i], ifriction[i], icohesion[i], idamping[i], ipenalty[i]};
      d_.interactions.push_back(in);
    }
  }

  void readDomain() {
    auto& d = d_.domain;
    const auto lo = table<double>(layout::kDomainLo, 3);
    const auto hi = table<double>(layout::kDomainHi, 3);
    d.lo = vec3At(lo, 0);
    d.hi = vec3At(hi, 0);
    const auto blocks = table<std::int32_t>(layout::kDomainBlocks, 3);
    const auto periodic = table<std::uint8_t>(layout::kDomainPeriodic, 3);
    std::int64_t count = 1;
    for (int a = 0; a < 3; ++a) {
      d.blocks[a] = blocks[a];
      d.periodic[a] = periodic[a] != 0;
      count *= blocks[a];
    }
    d.ranks = f_.readAttribute<std::int32_t>("/domain", "ranks");
    if (blocks[0] < 1 || blocks[1] < 1 || blocks[2] < 1) {
      throw inconsistent(cat(layout::kDomainBlocks.name, ": block counts below 1"));
    }
    const auto map = table<std::int32_t>(layout::kDomainRankMap, static_cast<std::uint64_t>(count));
    for (auto r : map) {
      if (r < 0 || r >= d.ranks) {
        throw inconsistent(cat(layout::kDomainRankMap.name, ": rank ", r, " of ", d.ranks));
      }
    }
    d.rank_map.assign(map.begin(), map.end());
  }

  template <typename T>
  std::vector<T> particleField(const layout::Dataset& d, std::size_t cols) {
    return f_.read<T>(d.name, cols, particle_slice_, replicated_);
  }

  void readParticles() {
    const std::uint64_t n = rows(layout::kUid);
    replicated_ = f_.readAttribute<std::uint64_t>("/particles", "replicated_count");
    if (replicated_ > n) {
      throw inconsistent(
          cat("/particles: replicated_count ", replicated_, " exceeds the ", n, " particles"));
    }
    const int rank = mpi::rank(comm_), ranks = mpi::size(comm_);
    particle_slice_ = h5::readerSlice(n - replicated_, rank, ranks);
    particle_slice_.offset += replicated_;
    particle_slice_.total = n;
    const auto uid = particleField<std::uint64_t>(layout::kUid, 1);
    const auto shape = particleField<std::int32_t>(layout::kShape, 1);
    const auto material = particleField<std::int32_t>(layout::kMaterial, 1);
    const auto flags = particleField<std::uint32_t>(layout::kFlags, 1);
    const auto driver = particleField<std::int32_t>(layout::kDriver, 1);
    const auto position = particleField<double>(layout::kPosition, 3);
    const auto orientation = particleField<double>(layout::kOrientation, 4);
    const auto velocity = particleField<double>(layout::kVelocity, 3);
    const auto angular_momentum = particleField<double>(layout::kAngularMomentum, 3);

    std::optional<std::string> problem;
    const auto n_shapes = static_cast<std::int32_t>(d_.shapes.size());
    const auto n_materials = static_cast<std::int32_t>(d_.materials.size());
    d_.particles.resize(uid.size());
    for (std::size_t i = 0; i < uid.size(); ++i) {
      Particle& p = d_.particles[i];
      p.uid = uid[i];
      p.shape = shape[i];
      p.material = material[i];
      p.flags = flags[i];
      p.driver = driver[i];
      p.position = vec3At(position, i);
      const double* q = orientation.data() + 4 * i;
      p.orientation = Quat(q[0], q[1], q[2], q[3]);
      p.velocity = vec3At(velocity, i);
      p.angular_momentum = vec3At(angular_momentum, i);
      const bool should_be_global = i < replicated_;
      if (problem) continue;
      if (p.shape < 0 || p.shape >= n_shapes || p.material < 0 || p.material >= n_materials) {
        problem = cat("particle uid ", p.uid, " has shape ", p.shape, " and material ", p.material,
                      " but the tables have ", n_shapes, " and ", n_materials);
      } else if (p.isGhost() || p.isGlobal() != should_be_global) {
        problem = cat("particle uid ", p.uid, " has flags ", p.flags, " but is stored among the ",
                      should_be_global ? "replicated" : "free", " particles");
      }
    }
    if (problem) problem = f_.context("/particles: " + *problem + " (inconsistent data)");
    h5::agree(problem, comm_);
  }

  void readContacts() {
    const std::uint64_t m = rows(layout::kPair);
    const h5::Slice slice = h5::readerSlice(m, mpi::rank(comm_), mpi::size(comm_));
    const auto pair = f_.read<std::uint64_t>(layout::kPair.name, 2, slice);
    const auto shear = f_.read<double>(layout::kShearForce.name, 3, slice);
    const auto normal = f_.read<double>(layout::kNormal.name, 3, slice);
    const auto warm_direction = f_.read<double>(layout::kWarmDirection.name, 3, slice);
    const auto warm_point = f_.read<double>(layout::kWarmPoint.name, 3, slice);
    const auto warm_valid = f_.read<std::uint32_t>(layout::kWarmValid.name, 1, slice);
    const auto reserved = f_.read<std::uint32_t>(layout::kKernelReserved.name, 1, slice);
    const auto touching = f_.read<std::uint32_t>(layout::kTouching.name, 1, slice);
    std::optional<std::string> problem;
    d_.pair_keys.resize(slice.rows);
    d_.pair_histories.resize(slice.rows);
    for (std::size_t i = 0; i < slice.rows; ++i) {
      auto& key = d_.pair_keys[i];
      key = {pair[2 * i], pair[2 * i + 1]};
      if (!(key.lo < key.hi) && !problem) {
        problem = f_.context(cat(layout::kPair.name, ": row ", slice.offset + i, " (", key.lo, ", ",
                                 key.hi, ") is not ordered lo < hi (inconsistent data)"));
      }
      auto& h = d_.pair_histories[i];
      h.shear_force = vec3At(shear, i);
      h.normal = vec3At(normal, i);
      h.kernel.warm_direction = vec3At(warm_direction, i);
      h.kernel.warm_point = vec3At(warm_point, i);
      h.kernel.warm_valid = warm_valid[i];
      h.kernel.reserved = reserved[i];
      h.touching = touching[i];
    }
    h5::agree(problem, comm_);
  }

  h5::File& f_;
  MPI_Comm comm_;
  CheckpointData d_;
  h5::Slice particle_slice_;
  std::uint64_t replicated_ = 0;
};

}  // namespace

CheckpointData readCheckpointVerified(const std::filesystem::path& path, MPI_Comm comm,
                                      const CheckpointIoOptions& options,
                                      std::vector<CheckpointDatasetInfo>* datasets) {
  const h5::ErrorSilencer silence;
  h5::File file = h5::File::open(path, comm, options);
  CheckpointData data = Reader(file).run();
  if (datasets) *datasets = file.datasets();
  file.close();
  return data;
}

CheckpointData readCheckpoint(const std::filesystem::path& path, MPI_Comm comm,
                              const CheckpointIoOptions& options) {
  return readCheckpointVerified(path, comm, options, nullptr);
}

}  // namespace polydem::io

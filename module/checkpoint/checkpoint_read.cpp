// readCheckpoint: every dataset read, its type, shape and checksum verified, and the contents
// checked for consistency (offsets, index ranges, the replicated rows, the exact time).
#include <algorithm>
#include <cmath>
#include <cstring>

#include "polydem/checkpoint/checkpoint.h"
#include "polydem/checkpoint/checkpoint_layout.h"
#include "polydem/checkpoint/checkpoint_read_all.h"
#include "polydem/core/error.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/state_hash.h"
#include "polydem/core/strings.h"
#include "polydem/hdf5/checksum.h"
#include "polydem/hdf5/file_digest.h"
#include "polydem/hdf5/hdf5_file.h"

namespace polydem::checkpoint {

namespace {

using particles::PairHistory;
using particles::PairKey;
using particles::Particle;

bool sameBits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

Vec3 vec3At(const std::vector<double>& v, std::size_t row) {
  return {v[3 * row], v[3 * row + 1], v[3 * row + 2]};
}
Vec3 vec3At(const double* v) {
  return {v[0], v[1], v[2]};
}

}  // namespace

std::optional<std::string> stepTimeProblem(const sim::CheckpointData& d) {
  if (d.step < 0 || d.equilibrium_steps < 0) {
    return cat("step ", d.step, " or equilibrium_steps ", d.equilibrium_steps, " is negative");
  }
  if (d.stage == sim::CheckpointStage::kEquilibrium && d.equilibrium_steps != d.step) {
    return cat("equilibrium stage at step ", d.step, " but equilibrium_steps is ",
               d.equilibrium_steps);
  }
  if (!(d.dt > 0.0) || !std::isfinite(d.dt)) return cat("dt ", d.dt, " is not a positive number");
  // step x dt exactly: the rounded product plus its rounding error (exact by fma).
  const auto n = static_cast<double>(d.step);
  const double product = n * d.dt;
  ExactSum exact;
  exact.add(product);
  exact.add(std::fma(n, d.dt, -product));
  if (d.step > (std::int64_t{1} << 53) ||
      exact.digits() != ExactSum::fromDigits(d.time_digits).digits()) {
    return cat("time ", d.time, " s is not step ", d.step, " x dt ", d.dt, " s");
  }
  return std::nullopt;
}

namespace {

/// One column of a table being read: its dataset and the buffer of one round.
template <typename T>
struct ReadColumn {
  ReadColumn(hdf5::File& f, const layout::Dataset& d, std::uint64_t total, std::size_t cols_)
      : dataset(f.open<T>(d.name, total, cols_)), cols(cols_) {}
  const T* row(std::size_t i) const { return buffer.data() + i * cols; }
  void read(std::uint64_t first_row, std::uint64_t rows) {
    buffer.resize(rows * cols);
    dataset.read(buffer.data(), first_row, rows);
  }
  void hash(std::size_t from, std::uint64_t count, std::uint64_t first_row) {
    dataset.hash(row(from), first_row, count);
  }

  hdf5::Dataset dataset;
  std::size_t cols;
  std::vector<T> buffer;
};

class Reader {
 public:
  explicit Reader(hdf5::File& file) : f_(file), comm_(file.comm()) {}

  sim::CheckpointData run() {
    readRoot();
    readRun();
    readShapes();
    readMaterials();
    readDomain();
    if (d_.format_version >= 6) readBolts();
    readParticles();
    readContacts();
    if (d_.format_version >= 2) readSubContacts();
    refuseUnread();
    return std::move(d_);
  }

 private:
  /// Thrown where every rank finds the same problem (replicated data); distributed problems go
  /// through hdf5::agree.
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
    return f_.readTable<T>(d.name, n, cols);
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
    d_.code_version = f_.readStringAttribute("/", "code_version");
    if (d_.format_version < kOldestReadableCheckpointVersion ||
        d_.format_version > kCheckpointFormatVersion) {
      throw inconsistent(cat("format version ", d_.format_version, " (written by polydem ",
                             d_.code_version, "); this polydem reads versions ",
                             kOldestReadableCheckpointVersion, " to ", kCheckpointFormatVersion,
                             " (docs/checkpoint.md, 'Older files')"));
    }
    verifyDigest();
    d_.writer_ranks = f_.readAttribute<std::int32_t>("/", "writer_ranks");
    if (d_.writer_ranks < 1) throw inconsistent(cat("writer_ranks ", d_.writer_ranks, " < 1"));
  }

  /// The digest first: an edited or mixed file is refused as such, before any of its values is
  /// looked at (hdf5/file_digest.h).
  /// Files older than the digest (versions 1 and 2) are read on their per-dataset checksums alone;
  /// d_.digest stays 0 and the restart says so.
  void verifyDigest() {
    digest_ = f_.digest();
    if (d_.format_version < kFirstDigestCheckpointVersion) return;
    const auto stored = f_.readAttribute<std::uint64_t>("/", hdf5::kDigestAttribute);
    if (stored != digest_.digest) {
      throw inconsistent(cat("the file was changed after it was written: its whole-file digest is ",
                             BitHasher::hex(stored), " but its groups, datasets and attributes ",
                             "hash to ", BitHasher::hex(digest_.digest), " (an edited file, or ",
                             "one with datasets from another checkpoint, cannot continue a run)"));
    }
    d_.digest = stored;
  }

  /// Every dataset of the file was read and verified: one the reader does not know is refused
  /// rather than ignored.
  void refuseUnread() const {
    const auto& read = f_.datasets();
    for (const auto& path : digest_.datasets) {
      const bool known =
          std::any_of(read.begin(), read.end(),
                      [&](const hdf5::CheckpointDatasetInfo& d) { return d.name == path; });
      if (!known) {
        throw inconsistent(cat("dataset ", path, " is not part of a version ",
                               kCheckpointFormatVersion, " checkpoint (inconsistent data)"));
      }
    }
  }

  void readRun() {
    d_.step = f_.readAttribute<std::int64_t>("/run", "step");
    d_.time = f_.readAttribute<double>("/run", "time");
    d_.dt = f_.readAttribute<double>("/run", "dt");
    const auto digits = f_.readAttribute<std::int64_t>("/run", "time_digits", ExactSum::kDigits);
    std::copy(digits.begin(), digits.end(), d_.time_digits.begin());
    const auto stage = f_.readAttribute<std::int32_t>("/run", "stage");
    if (stage != 0 && stage != 1) throw inconsistent(cat("/run: stage ", stage, " is not 0 or 1"));
    d_.stage = static_cast<sim::CheckpointStage>(stage);
    d_.equilibrium_steps = f_.readAttribute<std::int64_t>("/run", "equilibrium_steps");
    d_.equilibrium_reached = f_.readAttribute<std::uint8_t>("/run", "equilibrium_reached") != 0;
    const double exact = ExactSum::fromDigits(d_.time_digits).value();
    if (!sameBits(exact, d_.time)) {
      throw inconsistent(cat("/run: time ", d_.time, " is not the rounded time_digits ", exact));
    }
    if (const auto problem = stepTimeProblem(d_)) throw inconsistent("/run: " + *problem);
    d_.run_state = f_.readText(layout::kRunState.name);

    d_.scene_toml = f_.readText(layout::kSceneToml.name);
    d_.scene_file = f_.readStringAttribute("/scene", "file_name");
    d_.scene_hash = f_.readAttribute<std::uint64_t>("/scene", "hash");
    if (hdf5::checksumOfBytes(d_.scene_toml) != d_.scene_hash) {
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
    // Version 4 added the faces' joint planes; older files have none (saved_state.h).
    const bool planes = d_.format_version >= 4;
    const auto face_plane = planes ? table<std::int32_t>(layout::kShapeFacePlane, n_faces)
                                   : std::vector<std::int32_t>{};

    for (std::uint64_t s = 0; s < n; ++s) {
      sim::CheckpointShape shape;
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
      if (planes) {
        shape.face_plane.emplace(face_plane.begin() + face_offset[s],
                                 face_plane.begin() + face_offset[s + 1]);
      }
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
    // Version 1 predates joint stiffnesses: they were 0 (per-pair springs only).
    const bool joints = d_.format_version >= 2;
    const auto jkn = joints ? table<double>(layout::kMaterialJkn, n) : std::vector<double>(n, 0.0);
    const auto jks = joints ? table<double>(layout::kMaterialJks, n) : std::vector<double>(n, 0.0);
    for (std::uint64_t i = 0; i < n; ++i) {
      d_.materials.push_back({names[i], density[i], kn[i], ks[i], friction[i], cohesion[i],
                              normal_damping[i], local_damping[i], penalty[i], jkn[i], jks[i]});
    }
    const std::uint64_t k = rows(layout::kInteractionPair);
    const auto pairs = table<std::int32_t>(layout::kInteractionPair, k, 2);
    const auto ikn = table<double>(layout::kInteractionKn, k);
    const auto iks = table<double>(layout::kInteractionKs, k);
    const auto ifriction = table<double>(layout::kInteractionFriction, k);
    const auto icohesion = table<double>(layout::kInteractionCohesion, k);
    const auto idamping = table<double>(layout::kInteractionNormalDamping, k);
    const auto ipenalty = table<double>(layout::kInteractionPenalty, k);
    const auto ijkn =
        joints ? table<double>(layout::kInteractionJkn, k) : std::vector<double>(k, 0.0);
    const auto ijks =
        joints ? table<double>(layout::kInteractionJks, k) : std::vector<double>(k, 0.0);
    for (std::uint64_t i = 0; i < k; ++i) {
      setup::Setup::Interaction in;
      in.a = pairs[2 * i];
      in.b = pairs[2 * i + 1];
      if (in.a < 0 || static_cast<std::uint64_t>(in.a) >= n || in.b < 0 ||
          static_cast<std::uint64_t>(in.b) >= n) {
        throw inconsistent(cat(layout::kInteractionPair.name, ": row ", i, " names material (",
                               in.a, ", ", in.b, ") of ", n));
      }
      in.properties = {ikn[i],      iks[i],      ifriction[i], icohesion[i],
                       idamping[i], ipenalty[i], ijkn[i],      ijks[i]};
      d_.interactions.push_back(in);
    }
  }

  // Version 6 added the bolts' state; older files hold none (a scene without bolts).
  void readBolts() {
    const std::uint64_t n = rows(layout::kBoltAxialPlastic);
    const auto axial = table<double>(layout::kBoltAxialPlastic, n);
    const auto shear = table<double>(layout::kBoltShearPlastic, n, 3);
    const auto broken = table<std::uint8_t>(layout::kBoltBroken, n);
    for (std::uint64_t i = 0; i < n; ++i) {
      if (broken[i] > 1) throw inconsistent(cat(layout::kBoltBroken.name, ": row ", i, " not 0/1"));
      dynamics::BoltJointState b;
      b.axial_plastic = axial[i];
      b.shear_plastic = vec3At(shear, i);
      b.broken = broken[i] == 1;
      d_.bolt_states.push_back(b);
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

  /// Reads a table in collective rounds (few large transfers): every rank reads rows
  /// [0, prefix) (replicated rows, counted in the checksums on rank 0 only), then its `slice`.
  /// Each round is hashed and handed to unpack(from, count) (buffer rows [from, from + count),
  /// which the caller appends) block by block, while each block is in cache.
  template <typename Unpack, typename... Columns>
  void stream(std::uint64_t prefix, const hdf5::Slice& slice, std::size_t row_bytes, Unpack unpack,
              Columns&... columns) {
    const bool rank0 = mpi::rank(comm_) == 0;
    const std::size_t round_bytes = f_.options().round_bytes;
    auto run = [&](const hdf5::Slice& part, bool hashed) {
      const hdf5::Rounds rounds(part, row_bytes, round_bytes);
      for (std::uint64_t k = 0; k < rounds.count; ++k) {
        const std::uint64_t b = rounds.begin(k), e = rounds.end(k);
        (columns.read(part.offset + b, e - b), ...);
        for (std::uint64_t sb = b; sb < e; sb += layout::kBlockRows) {
          const std::uint64_t se = std::min(e, sb + layout::kBlockRows);
          if (hashed) (columns.hash(sb - b, se - sb, part.offset + sb), ...);
          unpack(sb - b, se - sb);
        }
      }
    };
    run(hdf5::Slice{0, prefix, slice.total, prefix}, rank0);
    run(slice, true);
    hdf5::Dataset* all[] = {&columns.dataset...};
    f_.finish(all);
  }

  void readParticles() {
    const std::uint64_t n = rows(layout::kUid);
    replicated_ = f_.readAttribute<std::uint64_t>("/particles", "replicated_count");
    if (replicated_ > n) {
      throw inconsistent(
          cat("/particles: replicated_count ", replicated_, " exceeds the ", n, " particles"));
    }
    const int rank = mpi::rank(comm_), ranks = mpi::size(comm_);
    hdf5::Slice slice = hdf5::readerSlice(n - replicated_, rank, ranks);
    slice.offset += replicated_;
    slice.total = n;
    ReadColumn<std::uint64_t> uid(f_, layout::kUid, n, 1);
    ReadColumn<std::int32_t> shape(f_, layout::kShape, n, 1);
    ReadColumn<std::int32_t> material(f_, layout::kMaterial, n, 1);
    ReadColumn<std::uint32_t> flags(f_, layout::kFlags, n, 1);
    ReadColumn<std::int32_t> driver(f_, layout::kDriver, n, 1);
    ReadColumn<double> position(f_, layout::kPosition, n, 3);
    ReadColumn<double> orientation(f_, layout::kOrientation, n, 4);
    ReadColumn<double> velocity(f_, layout::kVelocity, n, 3);
    ReadColumn<double> momentum(f_, layout::kAngularMomentum, n, 3);

    std::optional<std::string> problem;
    const auto n_shapes = static_cast<std::int32_t>(d_.shapes.size());
    const auto n_materials = static_cast<std::int32_t>(d_.materials.size());
    // Reserved, then appended block by block (rows come in file order): every byte of the new
    // memory is written once, without a zeroing pass first.
    d_.particles.reserve(replicated_ + slice.rows);
    auto unpack = [&](std::uint64_t from, std::uint64_t count) {
      for (std::uint64_t i = from; i < from + count; ++i) {
        const std::uint64_t at = d_.particles.size();
        Particle& p = d_.particles.emplace_back();
        p.uid = *uid.row(i);
        p.shape = *shape.row(i);
        p.material = *material.row(i);
        p.flags = *flags.row(i);
        p.driver = *driver.row(i);
        p.position = vec3At(position.row(i));
        const double* q = orientation.row(i);
        p.orientation = Quat(q[0], q[1], q[2], q[3]);
        p.velocity = vec3At(velocity.row(i));
        p.angular_momentum = vec3At(momentum.row(i));
        if (problem) continue;
        const bool should_be_global = at < replicated_;
        if (p.shape < 0 || p.shape >= n_shapes || p.material < 0 || p.material >= n_materials) {
          problem = cat("particle uid ", p.uid, " has shape ", p.shape, " and material ",
                        p.material, " but the tables have ", n_shapes, " and ", n_materials);
        } else if (p.isGhost() || p.isGlobal() != should_be_global) {
          problem = cat("particle uid ", p.uid, " has flags ", p.flags, " but is stored among the ",
                        should_be_global ? "replicated" : "free", " particles");
        }
      }
    };
    stream(replicated_, slice, layout::kParticleRowBytes, unpack, uid, shape, material, flags,
           driver, position, orientation, velocity, momentum);
    if (problem) problem = f_.context("/particles: " + *problem + " (inconsistent data)");
    hdf5::agree(problem, comm_);
  }

  void readContacts() {
    const std::uint64_t m = rows(layout::kPair);
    const hdf5::Slice slice = hdf5::readerSlice(m, mpi::rank(comm_), mpi::size(comm_));
    ReadColumn<std::uint64_t> pair(f_, layout::kPair, m, 2);
    ReadColumn<double> shear(f_, layout::kShearForce, m, 3);
    ReadColumn<double> normal(f_, layout::kNormal, m, 3);
    ReadColumn<double> warm_direction(f_, layout::kWarmDirection, m, 3);
    ReadColumn<double> warm_point(f_, layout::kWarmPoint, m, 3);
    ReadColumn<std::uint32_t> warm_valid(f_, layout::kWarmValid, m, 1);
    ReadColumn<std::uint32_t> reserved(f_, layout::kKernelReserved, m, 1);
    ReadColumn<std::uint32_t> touching(f_, layout::kTouching, m, 1);
    std::optional<std::string> problem;
    d_.pair_keys.reserve(slice.rows);
    d_.pair_histories.reserve(slice.rows);
    auto unpack = [&](std::uint64_t from, std::uint64_t count) {
      for (std::uint64_t i = from; i < from + count; ++i) {
        const std::uint64_t at = d_.pair_keys.size();
        const PairKey& key = d_.pair_keys.emplace_back(PairKey{pair.row(i)[0], pair.row(i)[1]});
        if (!(key.lo < key.hi) && !problem) {
          problem =
              f_.context(cat(layout::kPair.name, ": row ", slice.offset + at + i, " (", key.lo,
                             ", ", key.hi, ") is not ordered lo < hi (inconsistent data)"));
        }
        PairHistory& h = d_.pair_histories.emplace_back();
        h.shear_force = vec3At(shear.row(i));
        h.normal = vec3At(normal.row(i));
        h.kernel.warm_direction = vec3At(warm_direction.row(i));
        h.kernel.warm_point = vec3At(warm_point.row(i));
        h.kernel.warm_valid = *warm_valid.row(i);
        h.kernel.reserved = *reserved.row(i);
        h.touching = *touching.row(i);
      }
    };
    stream(0, slice, layout::kPairRowBytes, unpack, pair, shear, normal, warm_direction, warm_point,
           warm_valid, reserved, touching);
    hdf5::agree(problem, comm_);
  }

  void readSubContacts() {
    const std::uint64_t m = rows(layout::kSubPair);
    const hdf5::Slice slice = hdf5::readerSlice(m, mpi::rank(comm_), mpi::size(comm_));
    ReadColumn<std::uint64_t> pair(f_, layout::kSubPair, m, 2);
    ReadColumn<std::uint64_t> feature(f_, layout::kSubFeature, m, 1);
    ReadColumn<double> shear(f_, layout::kSubShearForce, m, 3);
    ReadColumn<double> normal(f_, layout::kSubNormal, m, 3);
    std::optional<ReadColumn<double>> law_state;
    std::optional<std::string> problem;
    d_.sub_keys.reserve(slice.rows);
    d_.sub_histories.reserve(slice.rows);
    auto unpack = [&](std::uint64_t from, std::uint64_t count) {
      for (std::uint64_t i = from; i < from + count; ++i) {
        const std::uint64_t at = d_.sub_keys.size();
        const particles::SubKey& key = d_.sub_keys.emplace_back(
            particles::SubKey{{pair.row(i)[0], pair.row(i)[1]}, *feature.row(i)});
        if (!(key.pair.lo < key.pair.hi) && !problem) {
          problem = f_.context(cat(layout::kSubPair.name, ": row ", slice.offset + at + i, " (",
                                   key.pair.lo, ", ", key.pair.hi,
                                   ") is not ordered lo < hi (inconsistent data)"));
        }
        particles::SubHistory& h = d_.sub_histories.emplace_back();
        h.shear_force = vec3At(shear.row(i));
        h.normal = vec3At(normal.row(i));
        if (law_state) std::copy_n(law_state->row(i), h.law.size(), h.law.begin());
      }
    };
    // Version 5 added the joint laws' history; older files continue with it 0 (intact joints,
    // not yet sheared: docs/checkpoint.md, 'Older files').
    if (d_.format_version >= 5) {
      law_state.emplace(f_, layout::kSubLawState, m, particles::kMaxLawHistory);
      stream(0, slice, layout::kSubRowBytes, unpack, pair, feature, shear, normal, *law_state);
    } else {
      stream(0, slice, layout::kSubRowBytes - particles::kMaxLawHistory * 8, unpack, pair, feature,
             shear, normal);
    }
    hdf5::agree(problem, comm_);
  }

  hdf5::File& f_;
  MPI_Comm comm_;
  sim::CheckpointData d_;
  hdf5::FileDigest digest_;
  std::uint64_t replicated_ = 0;
};

}  // namespace

sim::CheckpointData readCheckpointVerified(const std::filesystem::path& path, MPI_Comm comm,
                                           const hdf5::CheckpointIoOptions& options,
                                           std::vector<hdf5::CheckpointDatasetInfo>* datasets) {
  const hdf5::ErrorSilencer silence;
  hdf5::File file = hdf5::File::open(path, comm, options);
  sim::CheckpointData data = Reader(file).run();
  if (datasets) *datasets = file.datasets();
  file.close();
  return data;
}

sim::CheckpointData readCheckpoint(const std::filesystem::path& path, MPI_Comm comm,
                                   const hdf5::CheckpointIoOptions& options) {
  return readCheckpointVerified(path, comm, options, nullptr);
}

}  // namespace polydem::checkpoint

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

std::uint64_t rowsOf(const hdf5::File& f, const layout::Dataset& d) {
  const auto dims = f.dims(d.name);
  if (dims.empty()) throw CheckpointError(f.context(cat("dataset ", d.name, " is a scalar")));
  return dims[0];
}

/// The pair table's columns (/contacts), one round at a time.
struct PairColumns {
  PairColumns(hdf5::File& f, int /*format_version*/)
      : total(rowsOf(f, layout::kPair)),
        pair(f, layout::kPair, total, 2),
        shear(f, layout::kShearForce, total, 3),
        normal(f, layout::kNormal, total, 3),
        warm_direction(f, layout::kWarmDirection, total, 3),
        warm_point(f, layout::kWarmPoint, total, 3),
        warm_valid(f, layout::kWarmValid, total, 1),
        reserved(f, layout::kKernelReserved, total, 1),
        touching(f, layout::kTouching, total, 1) {}
  std::size_t rowBytes() const { return layout::kPairRowBytes; }
  template <typename F>
  void each(F f) {
    f(pair), f(shear), f(normal), f(warm_direction), f(warm_point), f(warm_valid), f(reserved),
        f(touching);
  }
  void reserve(particles::HistoryRecords& chunk, std::uint64_t rows) {
    chunk.keys.reserve(rows);
    chunk.entries.reserve(rows);
  }
  /// Rows [from, from + count) of the round, file rows from `first_row`, appended to `chunk`.
  void unpack(std::uint64_t from, std::uint64_t count, std::uint64_t first_row,
              particles::HistoryRecords& chunk, std::optional<std::string>& problem,
              const hdf5::File& f) {
    for (std::uint64_t i = from; i < from + count; ++i) {
      const PairKey& key = chunk.keys.emplace_back(PairKey{pair.row(i)[0], pair.row(i)[1]});
      if (!(key.lo < key.hi) && !problem) {
        problem = f.context(cat(layout::kPair.name, ": row ", first_row + i - from, " (", key.lo,
                                ", ", key.hi, ") is not ordered lo < hi (inconsistent data)"));
      }
      PairHistory& h = chunk.entries.emplace_back();
      h.shear_force = vec3At(shear.row(i));
      h.normal = vec3At(normal.row(i));
      h.kernel.warm_direction = vec3At(warm_direction.row(i));
      h.kernel.warm_point = vec3At(warm_point.row(i));
      h.kernel.warm_valid = *warm_valid.row(i);
      h.kernel.reserved = *reserved.row(i);
      h.touching = *touching.row(i);
    }
  }

  std::uint64_t total;
  ReadColumn<std::uint64_t> pair;
  ReadColumn<double> shear, normal, warm_direction, warm_point;
  ReadColumn<std::uint32_t> warm_valid, reserved, touching;
};

/// The sub-contact table's columns (/subcontacts). Version 5 added the joint laws' history;
/// older files continue with it 0 (intact joints, not yet sheared: docs/checkpoint.md, 'Older
/// files').
struct SubColumns {
  SubColumns(hdf5::File& f, int format_version)
      : total(rowsOf(f, layout::kSubPair)),
        pair(f, layout::kSubPair, total, 2),
        feature(f, layout::kSubFeature, total, 1),
        shear(f, layout::kSubShearForce, total, 3),
        normal(f, layout::kSubNormal, total, 3) {
    if (format_version >= 5)
      law_state.emplace(f, layout::kSubLawState, total, particles::kMaxLawHistory);
  }
  std::size_t rowBytes() const {
    return law_state ? layout::kSubRowBytes : layout::kSubRowBytes - particles::kMaxLawHistory * 8;
  }
  template <typename F>
  void each(F f) {
    f(pair), f(feature), f(shear), f(normal);
    if (law_state) f(*law_state);
  }
  void reserve(particles::HistoryRecords& chunk, std::uint64_t rows) {
    chunk.sub_keys.reserve(rows);
    chunk.sub_entries.reserve(rows);
  }
  void unpack(std::uint64_t from, std::uint64_t count, std::uint64_t first_row,
              particles::HistoryRecords& chunk, std::optional<std::string>& problem,
              const hdf5::File& f) {
    for (std::uint64_t i = from; i < from + count; ++i) {
      const particles::SubKey& key = chunk.sub_keys.emplace_back(
          particles::SubKey{{pair.row(i)[0], pair.row(i)[1]}, *feature.row(i)});
      if (!(key.pair.lo < key.pair.hi) && !problem) {
        problem =
            f.context(cat(layout::kSubPair.name, ": row ", first_row + i - from, " (", key.pair.lo,
                          ", ", key.pair.hi, ") is not ordered lo < hi (inconsistent data)"));
      }
      particles::SubHistory& h = chunk.sub_entries.emplace_back();
      h.shear_force = vec3At(shear.row(i));
      h.normal = vec3At(normal.row(i));
      if (law_state) std::copy_n(law_state->row(i), h.law.size(), h.law.begin());
    }
  }

  std::uint64_t total;
  ReadColumn<std::uint64_t> pair, feature;
  ReadColumn<double> shear, normal;
  std::optional<ReadColumn<double>> law_state;
};

/// The most bytes of history rows a rank reads per round: a restart routes each round's records
/// to their owners as one chunk, which holds a few times this in transit on every rank.
constexpr std::size_t kHistoryRoundBytes = std::size_t{8} << 20;

/// A history table read in collective rounds of the file's round size (few large transfers, a
/// bounded buffer): rank r of P reads slice r, one round per next(); each round is hashed block by
/// block while in cache, and the checksums are verified after the last.
template <typename Columns>
class TableRounds {
 public:
  TableRounds(hdf5::File& f, MPI_Comm comm, int format_version = 0)
      : f_(f),
        comm_(comm),
        columns_(f, format_version),
        slice_(hdf5::readerSlice(columns_.total, mpi::rank(comm), mpi::size(comm))),
        rounds_(slice_, columns_.rowBytes(),
                std::min(f.options().round_bytes, kHistoryRoundBytes)) {}

  /// The next round into `chunk` (appended), or false once every round is read and verified.
  bool next(particles::HistoryRecords& chunk) {
    if (k_ == rounds_.count) {
      std::vector<hdf5::Dataset*> all;
      columns_.each([&](auto& column) { all.push_back(&column.dataset); });
      f_.finish(all);
      hdf5::agree(problem_, comm_);
      return false;
    }
    const std::uint64_t b = rounds_.begin(k_), e = rounds_.end(k_);
    columns_.each([&](auto& column) { column.read(slice_.offset + b, e - b); });
    columns_.reserve(chunk, e - b);
    for (std::uint64_t sb = b; sb < e; sb += layout::kBlockRows) {
      const std::uint64_t se = std::min(e, sb + layout::kBlockRows);
      columns_.each([&](auto& column) { column.hash(sb - b, se - sb, slice_.offset + sb); });
      columns_.unpack(sb - b, se - sb, slice_.offset + sb, chunk, problem_, f_);
    }
    ++k_;
    return true;
  }

 private:
  hdf5::File& f_;
  MPI_Comm comm_;
  Columns columns_;
  hdf5::Slice slice_;
  hdf5::Rounds rounds_;
  std::uint64_t k_ = 0;
  std::optional<std::string> problem_;
};

class Reader {
 public:
  explicit Reader(hdf5::File& file) : f_(file), comm_(file.comm()) {}

  /// Everything but the pair histories (nextHistories reads them).
  void run() {
    readRoot();
    readRun();
    readShapes();
    readMaterials();
    readDomain();
    if (d_.format_version >= 6) readBolts();
    readParticles();
  }

  const sim::CheckpointData& data() const { return d_; }

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

 public:
  /// The next chunk of this rank's pair histories (one collective round of the pair table, then
  /// of the sub-contact table), or false once both are read and verified. Collective.
  bool nextHistories(particles::HistoryRecords& chunk) {
    chunk = {};
    while (true) {
      if (!pairs_ && phase_ == Phase::kPairs) pairs_.emplace(f_, comm_);
      if (!subs_ && phase_ == Phase::kSubs) subs_.emplace(f_, comm_, d_.format_version);
      if (pairs_) {
        if (pairs_->next(chunk)) return true;
        pairs_.reset();
        phase_ = d_.format_version >= 2 ? Phase::kSubs : Phase::kDone;
      } else if (subs_) {
        if (subs_->next(chunk)) return true;
        subs_.reset();
        phase_ = Phase::kDone;
      } else {
        return false;
      }
    }
  }

  /// After the last chunk: no dataset left unread.
  void finish() { refuseUnread(); }

  sim::CheckpointData take() { return std::move(d_); }

 private:
  enum class Phase { kPairs, kSubs, kDone };

  hdf5::File& f_;
  MPI_Comm comm_;
  sim::CheckpointData d_;
  hdf5::FileDigest digest_;
  std::uint64_t replicated_ = 0;
  Phase phase_ = Phase::kPairs;
  std::optional<TableRounds<PairColumns>> pairs_;
  std::optional<TableRounds<SubColumns>> subs_;
};

}  // namespace

// The open file and its reader; the silencer first, so that HDF5 prints nothing until the end.
struct CheckpointReader::Open {
  Open(const std::filesystem::path& path, MPI_Comm comm, const hdf5::CheckpointIoOptions& options)
      : file(hdf5::File::open(path, comm, options)), reader(file) {
    reader.run();
  }
  hdf5::ErrorSilencer silence;
  hdf5::File file;
  Reader reader;
};

CheckpointReader::CheckpointReader(const std::filesystem::path& path, MPI_Comm comm,
                                   const hdf5::CheckpointIoOptions& options)
    : open_(std::make_unique<Open>(path, comm, options)) {}

CheckpointReader::~CheckpointReader() = default;

const sim::CheckpointData& CheckpointReader::data() const {
  return open_->reader.data();
}

sim::CheckpointData CheckpointReader::takeData() {
  return open_->reader.take();
}

bool CheckpointReader::next(particles::HistoryRecords& chunk) {
  if (done_) {
    chunk = {};
    return false;
  }
  if (open_->reader.nextHistories(chunk)) return true;
  open_->reader.finish();
  datasets_ = open_->file.datasets();
  open_->file.close();
  done_ = true;
  return false;
}

sim::CheckpointData readCheckpointVerified(const std::filesystem::path& path, MPI_Comm comm,
                                           const hdf5::CheckpointIoOptions& options,
                                           std::vector<hdf5::CheckpointDatasetInfo>* datasets) {
  CheckpointReader reader(path, comm, options);
  particles::HistoryRecords all, chunk;
  auto append = [](auto& to, const auto& from) { to.insert(to.end(), from.begin(), from.end()); };
  while (reader.next(chunk)) {
    append(all.keys, chunk.keys);
    append(all.entries, chunk.entries);
    append(all.sub_keys, chunk.sub_keys);
    append(all.sub_entries, chunk.sub_entries);
  }
  sim::CheckpointData data = reader.takeData();
  data.pair_keys = std::move(all.keys);
  data.pair_histories = std::move(all.entries);
  data.sub_keys = std::move(all.sub_keys);
  data.sub_histories = std::move(all.sub_entries);
  if (datasets) *datasets = reader.datasets();
  return data;
}

sim::CheckpointData readCheckpoint(const std::filesystem::path& path, MPI_Comm comm,
                                   const hdf5::CheckpointIoOptions& options) {
  return readCheckpointVerified(path, comm, options, nullptr);
}

}  // namespace polydem::checkpoint

// The contents of a checkpoint file: attributes, replicated tables (one batch from rank 0), and
// the particle and pair tables streamed in collective rounds (internal to checkpoint, called by
// writeCheckpoint in checkpoint_write.cpp).
#include "polydem/checkpoint/checkpoint_writer.h"

#include <algorithm>
#include <tuple>

#include "polydem/checkpoint/checkpoint_layout.h"
#include "polydem/core/byte_buffer.h"
#include "polydem/core/mpi_env.h"
#include "polydem/hdf5/checksum.h"
#include "polydem/hdf5/file_digest.h"

namespace polydem::checkpoint {

namespace {

using particles::PairHistory;
using particles::PairKey;
using particles::Particle;

hdf5::Info info(const layout::Dataset& d) {
  return {d.units, d.description};
}

/// The replicated scalars and strings, as rank 0 has them: attributes must be written with the
/// same values on every rank, and one broadcast brings them all.
struct Header {
  std::string code_version, scene_file;
  std::int64_t step = 0, equilibrium_steps = 0;
  double time = 0.0, dt = 0.0;
  ExactSum::Digits time_digits{};
  std::int32_t stage = 0, domain_ranks = 0;
  std::uint8_t equilibrium_reached = 0;
  std::uint64_t scene_hash = 0, replicated_particles = 0;

  static Header fromRankZero(const sim::CheckpointData& d, MPI_Comm comm) {
    SendBuffer out;
    if (mpi::rank(comm) == 0) {
      std::uint64_t replicated = 0;
      for (const auto& p : d.particles) replicated += p.isGlobal();
      auto text = [&](const std::string& s) {
        out << static_cast<std::uint64_t>(s.size());
        out.append(s.data(), s.size());
      };
      text(d.code_version);
      text(d.scene_file);
      out << d.step << d.equilibrium_steps << d.time << d.dt << static_cast<std::int32_t>(d.stage)
          << static_cast<std::int32_t>(d.domain.ranks)
          << static_cast<std::uint8_t>(d.equilibrium_reached) << hdf5::checksumOfBytes(d.scene_toml)
          << replicated;
      for (auto digit : d.time_digits) out << digit;
    }
    std::uint64_t size = out.size();
    MPI_Bcast(&size, 1, MPI_UINT64_T, 0, comm);
    out.bytes().resize(size);
    MPI_Bcast(out.bytes().data(), static_cast<int>(size), MPI_BYTE, 0, comm);
    RecvBuffer in(out.bytes().data(), size);
    Header h;
    auto text = [&](std::string& s) {
      std::uint64_t n = 0;
      in >> n;
      s.resize(n);
      in.take(s.data(), n);
    };
    text(h.code_version);
    text(h.scene_file);
    in >> h.step >> h.equilibrium_steps >> h.time >> h.dt >> h.stage >> h.domain_ranks >>
        h.equilibrium_reached >> h.scene_hash >> h.replicated_particles;
    for (auto& digit : h.time_digits) in >> digit;
    return h;
  }
};

/// One column of a table being written: its dataset and the buffer of one round.
template <typename T>
struct Column {
  Column(hdf5::File& f, const layout::Dataset& d, std::uint64_t total, std::size_t cols_)
      : dataset(f.create<T>(d.name, total, cols_, info(d))), cols(cols_) {}
  T* row(std::size_t i) { return buffer.data() + i * cols; }
  void resize(std::uint64_t rows) { buffer.resize(rows * cols); }
  void hash(std::size_t from, std::uint64_t count, std::uint64_t first_row) {
    dataset.hash(row(from), first_row, count);
  }
  void write(std::uint64_t first_row, std::uint64_t rows) {
    dataset.write(buffer.data(), first_row, rows);
  }

  hdf5::Dataset dataset;
  std::size_t cols;
  std::vector<T> buffer;
};

void put(const Vec3& v, double* out) {
  out[0] = v.x();
  out[1] = v.y();
  out[2] = v.z();
}

template <typename Getter>
std::vector<double> column(const auto& items, Getter get) {
  std::vector<double> out;
  for (const auto& item : items) out.push_back(get(item));
  return out;
}

/// This rank's pair rows: the data's pair tables, or the pairs of its history view read in place.
class PairRows {
 public:
  explicit PairRows(const sim::CheckpointData& d) : d_(d), view_(d.history_view) {}
  std::size_t size() const { return view_.table ? view_.pairs.size() : d_.pair_keys.size(); }
  const PairKey& key(std::size_t r) const {
    return view_.table ? view_.table->keys()[view_.pairs[r]] : d_.pair_keys[r];
  }
  const PairHistory& history(std::size_t r) const {
    return view_.table ? view_.table->entries()[view_.pairs[r]] : d_.pair_histories[r];
  }

 private:
  const sim::CheckpointData& d_;
  const sim::HistoryView& view_;
};

/// This rank's sub-contact rows in order (next() once per row): the data's tables, or the blocks
/// of the view's pairs one after the other.
class SubRows {
 public:
  struct Row {
    PairKey pair;
    std::uint64_t feature = 0;
    const particles::SubHistory* history = nullptr;
  };
  explicit SubRows(const sim::CheckpointData& d)
      : d_(d), view_(d.history_view), size_(view_.table ? view_.subCount() : d.sub_keys.size()) {}
  std::size_t size() const { return size_; }
  Row next() {
    if (!view_.table) {
      const particles::SubKey& key = d_.sub_keys[row_];
      return {key.pair, key.feature, &d_.sub_histories[row_++]};
    }
    while (sub_ == sub_end_) {  // the next written pair's block (a pair may have none)
      std::tie(sub_, sub_end_) = view_.table->subsOf(view_.pairs[pair_]);
      pair_key_ = view_.table->keys()[view_.pairs[pair_++]];
    }
    const std::size_t s = sub_++;
    return {pair_key_, view_.table->subFeatures()[s].feature, &view_.table->subEntries()[s]};
  }

 private:
  const sim::CheckpointData& d_;
  const sim::HistoryView& view_;
  std::size_t size_;
  std::size_t row_ = 0, pair_ = 0, sub_ = 0, sub_end_ = 0;
  PairKey pair_key_;
};

class Writer {
 public:
  Writer(hdf5::File& file, const sim::CheckpointData& data)
      : f_(file),
        data_(data),
        comm_(file.comm()),
        rank_(mpi::rank(comm_)),
        header_(Header::fromRankZero(data, comm_)),
        batch_(comm_) {}

  void run() {
    writeGroups();
    addRun();
    addShapes();
    addMaterials();
    addDomain();
    addBolts();
    f_.write(batch_);
    writeParticles();
    writeContacts();
    writeSubContacts();
    // Last: the digest covers everything written above (hdf5/file_digest.h).
    f_.writeAttribute<std::uint64_t>("/", hdf5::kDigestAttribute, f_.digest().digest);
  }

 private:
  /// A replicated table of the batch (rank 0's values are written).
  template <typename T>
  void table(const layout::Dataset& d, const std::vector<T>& values, std::size_t cols) {
    batch_.table<T>(d.name, values, cols, info(d));
  }

  /// Moves a table of `slice` rows in collective rounds (few large transfers). Within a round,
  /// pack(begin, end, base) fills buffer rows [begin - base, end - base) of every column from this
  /// rank's rows [begin, end) in one pass over a cache-sized block, and the block is hashed while
  /// it is still in cache.
  template <typename Pack, typename... Columns>
  void stream(const hdf5::Slice& slice, std::size_t row_bytes, Pack pack, Columns&... columns) {
    const hdf5::Rounds rounds(slice, row_bytes, f_.options().round_bytes);
    for (std::uint64_t k = 0; k < rounds.count; ++k) {
      const std::uint64_t b = rounds.begin(k), e = rounds.end(k);
      (columns.resize(e - b), ...);
      for (std::uint64_t sb = b; sb < e; sb += layout::kBlockRows) {
        const std::uint64_t se = std::min(e, sb + layout::kBlockRows);
        pack(sb, se, b);
        (columns.hash(sb - b, se - sb, slice.offset + sb), ...);
      }
      (columns.write(slice.offset + b, e - b), ...);
    }
    hdf5::Dataset* all[] = {&columns.dataset...};
    f_.finish(all);
  }

  void writeGroups() {
    const Header& h = header_;
    f_.writeAttribute("/", "format", std::string(layout::kFormatName));
    f_.writeAttribute<std::int32_t>("/", "format_version", kCheckpointFormatVersion);
    f_.writeAttribute("/", "code_version", h.code_version);
    f_.writeAttribute<std::int32_t>("/", "writer_ranks", mpi::size(comm_));
    f_.writeAttribute("/", "checksum_algorithm", std::string(layout::kChecksumAlgorithm));
    f_.writeAttribute("/", "digest_algorithm", std::string(layout::kDigestAlgorithm));

    f_.createGroup("/run", "step, time and stage of the run");
    f_.writeAttribute("/run", "step", h.step);
    f_.writeAttribute("/run", "time", h.time);
    f_.writeAttribute("/run", "dt", h.dt);
    f_.writeAttribute("/run", "time_digits", std::span<const std::int64_t>(h.time_digits));
    f_.writeAttribute("/run", "stage", h.stage);
    f_.writeAttribute("/run", "stage_name",
                      std::string(sim::toString(static_cast<sim::CheckpointStage>(h.stage))));
    f_.writeAttribute("/run", "equilibrium_steps", h.equilibrium_steps);
    f_.writeAttribute("/run", "equilibrium_reached", h.equilibrium_reached);
    f_.createGroup("/scene", "the scene file the run was started from");
    f_.writeAttribute("/scene", "file_name", h.scene_file);
    f_.writeAttribute("/scene", "hash", h.scene_hash);
    f_.createGroup("/shapes", "shape table, body frame (centroid at the origin, principal axes)");
    f_.createGroup("/materials", "material table (rows are /particles/material)");
    f_.createGroup("/materials/interaction", "explicit contact properties of material pairs");
    f_.createGroup("/domain", "block forest of the writer (domain/block_forest.h)");
    f_.writeAttribute("/domain", "ranks", h.domain_ranks);
    f_.createGroup("/particles",
                   "particles: replicated (fixed, driven) rows first, then free ones");
    f_.writeAttribute("/particles", "replicated_count", h.replicated_particles);
    f_.createGroup("/contacts", "pair histories, one row per pair");
    f_.createGroup("/subcontacts", "sub-contact histories, one row per sub-contact in compression");
    f_.createGroup("/bolts", "state of every [[bolt]] at every joint it crosses (sim/bolts.h)");
  }

  void addRun() {
    batch_.text(layout::kRunState.name, data_.run_state, info(layout::kRunState));
    batch_.text(layout::kSceneToml.name, data_.scene_toml, info(layout::kSceneToml));
  }

  void addShapes() {
    std::vector<std::string> names;
    std::vector<std::int64_t> vertex_offset{0}, face_offset{0}, face_vertex_offset{0};
    std::vector<double> vertices, volume, moments, circumradius, inradius;
    std::vector<std::int32_t> face_vertices, face_plane;
    for (const auto& s : data_.shapes) {
      for (std::size_t f = 0; f < s.faces.size(); ++f)
        face_plane.push_back(s.face_plane ? (*s.face_plane)[f] : -1);
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
    batch_.strings(layout::kShapeName.name, names, info(layout::kShapeName));
    table(layout::kShapeVertexOffset, vertex_offset, 1);
    table(layout::kShapeVertices, vertices, 3);
    table(layout::kShapeFaceOffset, face_offset, 1);
    table(layout::kFaceVertexOffset, face_vertex_offset, 1);
    table(layout::kFaceVertices, face_vertices, 1);
    table(layout::kShapeVolume, volume, 1);
    table(layout::kShapeMoments, moments, 3);
    table(layout::kShapeCircumradius, circumradius, 1);
    table(layout::kShapeInradius, inradius, 1);
    table(layout::kShapeFacePlane, face_plane, 1);
  }

  void addMaterials() {
    using particles::Material;
    const auto& m = data_.materials;
    std::vector<std::string> names;
    for (const auto& x : m) names.push_back(x.name);
    batch_.strings(layout::kMaterialName.name, names, info(layout::kMaterialName));
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
    table(layout::kMaterialJkn, column(m, [](const Material& x) { return x.jkn; }), 1);
    table(layout::kMaterialJks, column(m, [](const Material& x) { return x.jks; }), 1);

    using In = setup::Setup::Interaction;
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
    table(layout::kInteractionJkn, column(in, [](const In& x) { return x.properties.jkn; }), 1);
    table(layout::kInteractionJks, column(in, [](const In& x) { return x.properties.jks; }), 1);
  }

  void addBolts() {
    std::vector<double> axial, shear;
    std::vector<std::uint8_t> broken;
    for (const auto& b : data_.bolt_states) {
      axial.push_back(b.axial_plastic);
      shear.insert(shear.end(), {b.shear_plastic.x(), b.shear_plastic.y(), b.shear_plastic.z()});
      broken.push_back(b.broken ? 1 : 0);
    }
    table(layout::kBoltAxialPlastic, axial, 1);
    table(layout::kBoltShearPlastic, shear, 3);
    table(layout::kBoltBroken, broken, 1);
  }

  void addDomain() {
    const auto& d = data_.domain;
    table(layout::kDomainLo, std::vector<double>{d.lo.x(), d.lo.y(), d.lo.z()}, 1);
    table(layout::kDomainHi, std::vector<double>{d.hi.x(), d.hi.y(), d.hi.z()}, 1);
    table(layout::kDomainBlocks, std::vector<std::int32_t>(d.blocks.begin(), d.blocks.end()), 1);
    std::vector<std::uint8_t> periodic;
    for (bool p : d.periodic) periodic.push_back(p ? 1 : 0);
    table(layout::kDomainPeriodic, periodic, 1);
    table(layout::kDomainRankMap, std::vector<std::int32_t>(d.rank_map.begin(), d.rank_map.end()),
          1);
  }

  void writeParticles() {
    // Rank 0 writes the replicated particles first, so that they are rows [0, G) of the file.
    std::vector<const Particle*> rows;
    if (rank_ == 0) {
      for (const auto& p : data_.particles) {
        if (p.isGlobal()) rows.push_back(&p);
      }
    }
    for (const auto& p : data_.particles) {
      if (!p.isGlobal()) rows.push_back(&p);
    }
    const hdf5::Slice slice = hdf5::writerSlice(rows.size(), comm_);
    const std::uint64_t n = slice.total;
    Column<std::uint64_t> uid(f_, layout::kUid, n, 1);
    Column<std::int32_t> shape(f_, layout::kShape, n, 1);
    Column<std::int32_t> material(f_, layout::kMaterial, n, 1);
    Column<std::uint32_t> flags(f_, layout::kFlags, n, 1);
    Column<std::int32_t> driver(f_, layout::kDriver, n, 1);
    Column<double> position(f_, layout::kPosition, n, 3);
    Column<double> orientation(f_, layout::kOrientation, n, 4);
    Column<double> velocity(f_, layout::kVelocity, n, 3);
    Column<double> momentum(f_, layout::kAngularMomentum, n, 3);
    auto pack = [&](std::uint64_t begin, std::uint64_t end, std::uint64_t base) {
      for (std::uint64_t r = begin; r < end; ++r) {
        const Particle& p = *rows[r];
        const std::size_t i = r - base;
        *uid.row(i) = p.uid;
        *shape.row(i) = p.shape;
        *material.row(i) = p.material;
        *flags.row(i) = p.flags;
        *driver.row(i) = p.driver;
        put(p.position, position.row(i));
        double* q = orientation.row(i);
        q[0] = p.orientation.w();
        q[1] = p.orientation.x();
        q[2] = p.orientation.y();
        q[3] = p.orientation.z();
        put(p.velocity, velocity.row(i));
        put(p.angular_momentum, momentum.row(i));
      }
    };
    stream(slice, layout::kParticleRowBytes, pack, uid, shape, material, flags, driver, position,
           orientation, velocity, momentum);
  }

  void writeContacts() {
    const PairRows rows(data_);
    const hdf5::Slice slice = hdf5::writerSlice(rows.size(), comm_);
    const std::uint64_t m = slice.total;
    Column<std::uint64_t> pair(f_, layout::kPair, m, 2);
    Column<double> shear(f_, layout::kShearForce, m, 3);
    Column<double> normal(f_, layout::kNormal, m, 3);
    Column<double> warm_direction(f_, layout::kWarmDirection, m, 3);
    Column<double> warm_point(f_, layout::kWarmPoint, m, 3);
    Column<std::uint32_t> warm_valid(f_, layout::kWarmValid, m, 1);
    Column<std::uint32_t> reserved(f_, layout::kKernelReserved, m, 1);
    Column<std::uint32_t> touching(f_, layout::kTouching, m, 1);
    auto pack = [&](std::uint64_t begin, std::uint64_t end, std::uint64_t base) {
      for (std::uint64_t r = begin; r < end; ++r) {
        const std::size_t i = r - base;
        const PairKey& key = rows.key(r);
        const PairHistory& h = rows.history(r);
        pair.row(i)[0] = key.lo;
        pair.row(i)[1] = key.hi;
        put(h.shear_force, shear.row(i));
        put(h.normal, normal.row(i));
        put(h.kernel.warm_direction, warm_direction.row(i));
        put(h.kernel.warm_point, warm_point.row(i));
        *warm_valid.row(i) = h.kernel.warm_valid;
        *reserved.row(i) = h.kernel.reserved;
        *touching.row(i) = h.touching;
      }
    };
    stream(slice, layout::kPairRowBytes, pack, pair, shear, normal, warm_direction, warm_point,
           warm_valid, reserved, touching);
  }

  void writeSubContacts() {
    SubRows rows(data_);
    const hdf5::Slice slice = hdf5::writerSlice(rows.size(), comm_);
    const std::uint64_t m = slice.total;
    Column<std::uint64_t> pair(f_, layout::kSubPair, m, 2);
    Column<std::uint64_t> feature(f_, layout::kSubFeature, m, 1);
    Column<double> shear(f_, layout::kSubShearForce, m, 3);
    Column<double> normal(f_, layout::kSubNormal, m, 3);
    Column<double> law_state(f_, layout::kSubLawState, m, particles::kMaxLawHistory);
    auto pack = [&](std::uint64_t begin, std::uint64_t end, std::uint64_t base) {
      for (std::uint64_t r = begin; r < end; ++r) {
        const std::size_t i = r - base;
        const SubRows::Row row = rows.next();
        pair.row(i)[0] = row.pair.lo;
        pair.row(i)[1] = row.pair.hi;
        *feature.row(i) = row.feature;
        put(row.history->shear_force, shear.row(i));
        put(row.history->normal, normal.row(i));
        std::copy(row.history->law.begin(), row.history->law.end(), law_state.row(i));
      }
    };
    stream(slice, layout::kSubRowBytes, pack, pair, feature, shear, normal, law_state);
  }

  hdf5::File& f_;
  const sim::CheckpointData& data_;
  MPI_Comm comm_;
  int rank_;
  Header header_;
  hdf5::ReplicatedBatch batch_;
};

}  // namespace

void writeContents(hdf5::File& file, const sim::CheckpointData& data) {
  Writer(file, data).run();
}

}  // namespace polydem::checkpoint

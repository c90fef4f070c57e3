// polydem bench checkpoint: write and read time and bandwidth of a checkpoint on the launched
// ranks, beside the peer measured in the same run: the same bytes written and read with plain
// parallel HDF5 (one dataset per field, collective transfers, no checksums, no attributes, no
// packing from particle structs, no rename), with and without the flush that makes the file
// durable (the checkpoint always flushes).
#include <hdf5.h>
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "polydem/checkpoint/checkpoint.h"
#include "polydem/core/error.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/hdf5/hdf5_types.h"

namespace polydem::app {

namespace {

namespace fs = std::filesystem;

/// One field as the raw peer writes it: this rank's rows, already contiguous.
struct RawField {
  std::string name;
  hid_t mem_type, file_type;
  std::size_t cols;
  std::size_t element_bytes;
  std::vector<std::byte> bytes;       // this rank's rows
  std::unique_ptr<std::byte[]> read;  // this rank's share when reading: fresh memory each time,
                                      // as a restart reads into memory it has not touched yet
};

/// Appends a column of `cols` values of type T, with the HDF5 types the checkpoint uses for T;
/// returns its byte buffer (a reference into `out`: reserve first).
template <typename T>
std::vector<std::byte>& addField(std::vector<RawField>& out, const char* name, std::size_t cols) {
  out.push_back({name, hdf5::Type<T>::mem(), hdf5::Type<T>::file(), cols, sizeof(T), {}, nullptr});
  return out.back().bytes;
}

struct Sample {
  sim::CheckpointData data;
  std::vector<RawField> particle_fields, pair_fields;
  std::uint64_t particles = 0, pairs = 0, payload_bytes = 0;  // global
};

class Lcg {
 public:
  explicit Lcg(std::uint64_t seed) : s_(seed * 0x9e3779b97f4a7c15ULL + 7) {}
  double next() {
    s_ = s_ * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(s_ >> 11) / 9007199254740992.0;
  }
  Vec3 vec3(double scale) { return scale * Vec3(next() - 0.5, next() - 0.5, next() - 0.5); }

 private:
  std::uint64_t s_;
};

template <typename T>
void appendBytes(std::vector<std::byte>& out, const T& value) {
  const auto* p = reinterpret_cast<const std::byte*>(&value);
  out.insert(out.end(), p, p + sizeof value);
}

void appendVec3(std::vector<std::byte>& out, const Vec3& v) {
  for (int i = 0; i < 3; ++i) appendBytes(out, v[i]);
}

/// `particles` particles over the ranks of `comm` (contiguous uids per rank), each in
/// `per_particle` pair histories with later uids, and the raw peer's copy of the same bytes.
Sample makeSample(std::int64_t particles, int per_particle, MPI_Comm comm) {
  const int rank = mpi::rank(comm), ranks = mpi::size(comm);
  const std::int64_t begin = particles * rank / ranks, end = particles * (rank + 1) / ranks;
  Sample s;
  sim::CheckpointData& d = s.data;
  d.code_version = version();
  d.scene_file = "bench.toml";
  d.scene_toml = "# synthetic checkpoint benchmark\n";
  d.step = 1000;
  d.dt = 1e-5;
  ExactSum time;  // as a time loop has it: step x dt
  for (std::int64_t i = 0; i < d.step; ++i) time.add(d.dt);
  d.time_digits = time.digits();
  d.time = time.value();
  sim::CheckpointShape cube;
  cube.name = "cube";
  for (int i = 0; i < 8; ++i)
    cube.vertices.emplace_back(i & 1 ? 0.5 : -0.5, i & 2 ? 0.5 : -0.5, i & 4 ? 0.5 : -0.5);
  cube.faces = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  cube.volume = 1.0;
  cube.principal_moments = Vec3::Constant(1.0 / 6.0);
  cube.circumradius = std::sqrt(0.75);
  cube.inradius = 0.5;
  d.shapes = {cube};
  d.materials = {{"rock", 2650, 1e9, 5e8, 30, 0, 0.1, 0, 0}};
  d.domain.hi = Vec3::Constant(100.0);
  d.domain.rank_map = {0};

  Lcg rng(static_cast<std::uint64_t>(rank) + 1);
  for (std::int64_t i = begin; i < end; ++i) {
    particles::Particle p;
    p.uid = static_cast<Uid>(i + 1);
    p.shape = 0;
    p.material = 0;
    p.position = rng.vec3(100.0) + Vec3::Constant(50.0);
    p.orientation = Quat(rng.next(), rng.next(), rng.next(), rng.next()).normalized();
    p.velocity = rng.vec3(1.0);
    p.angular_momentum = rng.vec3(10.0);
    d.particles.push_back(p);
    for (int k = 1; k <= per_particle; ++k) {
      particles::PairHistory h;
      h.shear_force = rng.vec3(1e3);
      h.normal = rng.vec3(1.0).normalized();
      h.kernel.warm_direction = rng.vec3(1.0);
      h.kernel.warm_point = p.position;
      h.kernel.warm_valid = 1;
      h.touching = static_cast<std::uint32_t>(k % 2);
      d.pair_keys.push_back({p.uid, p.uid + static_cast<Uid>(k)});
      d.pair_histories.push_back(h);
    }
  }

  // The raw peer's fields: the same values in the same row order.
  auto& pf = s.particle_fields;
  pf.reserve(9);  // addField() hands out references into these vectors: no reallocation
  s.pair_fields.reserve(8);
  auto& uid = addField<std::uint64_t>(pf, "uid", 1);
  auto& shape = addField<std::int32_t>(pf, "shape", 1);
  auto& material = addField<std::int32_t>(pf, "material", 1);
  auto& flags = addField<std::uint32_t>(pf, "flags", 1);
  auto& driver = addField<std::int32_t>(pf, "driver", 1);
  auto& position = addField<double>(pf, "position", 3);
  auto& orientation = addField<double>(pf, "orientation", 4);
  auto& velocity = addField<double>(pf, "velocity", 3);
  auto& momentum = addField<double>(pf, "angular_momentum", 3);
  for (const auto& p : d.particles) {
    appendBytes(uid, p.uid);
    appendBytes(shape, p.shape);
    appendBytes(material, p.material);
    appendBytes(flags, p.flags);
    appendBytes(driver, p.driver);
    appendVec3(position, p.position);
    for (double q : {p.orientation.w(), p.orientation.x(), p.orientation.y(), p.orientation.z()}) {
      appendBytes(orientation, q);
    }
    appendVec3(velocity, p.velocity);
    appendVec3(momentum, p.angular_momentum);
  }
  auto& hf = s.pair_fields;
  auto& pair = addField<std::uint64_t>(hf, "pair", 2);
  auto& shear = addField<double>(hf, "shear_force", 3);
  auto& normal = addField<double>(hf, "normal", 3);
  auto& warm_direction = addField<double>(hf, "warm_direction", 3);
  auto& warm_point = addField<double>(hf, "warm_point", 3);
  auto& warm_valid = addField<std::uint32_t>(hf, "warm_valid", 1);
  auto& reserved = addField<std::uint32_t>(hf, "kernel_reserved", 1);
  auto& touching = addField<std::uint32_t>(hf, "touching", 1);
  for (std::size_t i = 0; i < d.pair_keys.size(); ++i) {
    const auto& h = d.pair_histories[i];
    appendBytes(pair, d.pair_keys[i].lo);
    appendBytes(pair, d.pair_keys[i].hi);
    appendVec3(shear, h.shear_force);
    appendVec3(normal, h.normal);
    appendVec3(warm_direction, h.kernel.warm_direction);
    appendVec3(warm_point, h.kernel.warm_point);
    appendBytes(warm_valid, h.kernel.warm_valid);
    appendBytes(reserved, h.kernel.reserved);
    appendBytes(touching, h.touching);
  }
  s.particles = static_cast<std::uint64_t>(particles);
  s.pairs = static_cast<std::uint64_t>(
      mpi::allreduceSum(static_cast<std::int64_t>(d.pair_keys.size()), comm));
  std::uint64_t mine = 0;
  for (const auto* fields : {&s.particle_fields, &s.pair_fields}) {
    for (const auto& f : *fields) mine += f.bytes.size();
  }
  s.payload_bytes =
      static_cast<std::uint64_t>(mpi::allreduceSum(static_cast<std::int64_t>(mine), comm));
  return s;
}

/// The file access list both writers use: MPI-IO with collective metadata.
hid_t accessList(MPI_Comm comm) {
  const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_fapl_mpio(fapl, comm, MPI_INFO_NULL);
  H5Pset_libver_bounds(fapl, H5F_LIBVER_V18, H5F_LIBVER_LATEST);
  H5Pset_all_coll_metadata_ops(fapl, true);
  H5Pset_coll_metadata_write(fapl, true);
  return fapl;
}

void check(bool ok, const std::string& what) {
  if (!ok) throw Error("bench checkpoint: raw HDF5 peer: " + what + " failed");
}

/// Rows [offset, offset + rows) of `total` for this rank, as the hyperslab of `fields`.
void rawTransfer(hid_t file, std::vector<RawField>& fields, std::uint64_t rows,
                 std::uint64_t offset, std::uint64_t total, bool writing, hid_t dxpl) {
  for (auto& f : fields) {
    const hsize_t dims[2] = {total, f.cols};
    const int rank = f.cols > 1 ? 2 : 1;
    hid_t d;
    if (writing) {
      const hid_t space = H5Screate_simple(rank, dims, nullptr);
      const hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
      H5Pset_fill_time(dcpl, H5D_FILL_TIME_NEVER);
      H5Pset_alloc_time(dcpl, H5D_ALLOC_TIME_EARLY);
      d = H5Dcreate2(file, f.name.c_str(), f.file_type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
      H5Pclose(dcpl);
      H5Sclose(space);
    } else {
      d = H5Dopen2(file, f.name.c_str(), H5P_DEFAULT);
      f.read.reset(new std::byte[std::max<std::size_t>(rows * f.cols * f.element_bytes, 1)]);
    }
    check(d >= 0, "dataset " + f.name);
    const hid_t file_space = H5Dget_space(d);
    const hsize_t start[2] = {offset, 0}, count[2] = {rows, f.cols};
    const hsize_t elements = std::max<hsize_t>(rows * f.cols, 1);
    const hid_t mem_space = H5Screate_simple(1, &elements, nullptr);
    if (rows > 0) {
      H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start, nullptr, count, nullptr);
    } else {
      H5Sselect_none(file_space);
      H5Sselect_none(mem_space);
    }
    std::uint64_t dummy = 0;
    void* buffer = &dummy;
    if (rows > 0) buffer = writing ? f.bytes.data() : f.read.get();
    if (total > 0) {
      const herr_t status = writing ? H5Dwrite(d, f.mem_type, mem_space, file_space, dxpl, buffer)
                                    : H5Dread(d, f.mem_type, mem_space, file_space, dxpl, buffer);
      check(status >= 0, (writing ? "writing " : "reading ") + f.name);
    }
    H5Sclose(mem_space);
    H5Sclose(file_space);
    H5Dclose(d);
  }
}

std::uint64_t exclusiveSum(std::uint64_t value, MPI_Comm comm) {
  std::uint64_t before = 0;
  MPI_Exscan(&value, &before, 1, MPI_UINT64_T, MPI_SUM, comm);
  return mpi::rank(comm) == 0 ? 0 : before;
}

void rawWrite(const fs::path& path, Sample& s, MPI_Comm comm, bool flush) {
  const hid_t fapl = accessList(comm);
  const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
  H5Pclose(fapl);
  check(file >= 0, "creating " + path.string());
  const hid_t dxpl = H5Pcreate(H5P_DATASET_XFER);
  H5Pset_dxpl_mpio(dxpl, H5FD_MPIO_COLLECTIVE);
  const std::uint64_t n = s.data.particles.size(), m = s.data.pair_keys.size();
  rawTransfer(file, s.particle_fields, n, exclusiveSum(n, comm), s.particles, true, dxpl);
  rawTransfer(file, s.pair_fields, m, exclusiveSum(m, comm), s.pairs, true, dxpl);
  H5Pclose(dxpl);
  if (flush) H5Fflush(file, H5F_SCOPE_GLOBAL);
  check(H5Fclose(file) >= 0, "closing " + path.string());
}

void rawRead(const fs::path& path, Sample& s, MPI_Comm comm) {
  const hid_t fapl = accessList(comm);
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl);
  H5Pclose(fapl);
  check(file >= 0, "opening " + path.string());
  const hid_t dxpl = H5Pcreate(H5P_DATASET_XFER);
  H5Pset_dxpl_mpio(dxpl, H5FD_MPIO_COLLECTIVE);
  const auto r = static_cast<std::uint64_t>(mpi::rank(comm));
  const auto p = static_cast<std::uint64_t>(mpi::size(comm));
  for (auto [fields, total] :
       {std::pair{&s.particle_fields, s.particles}, std::pair{&s.pair_fields, s.pairs}}) {
    const std::uint64_t offset = total * r / p, rows = total * (r + 1) / p - offset;
    rawTransfer(file, *fields, rows, offset, total, false, dxpl);
  }
  H5Pclose(dxpl);
  check(H5Fclose(file) >= 0, "closing " + path.string());
  for (auto* fields : {&s.particle_fields, &s.pair_fields}) {
    for (auto& f : *fields) f.read.reset();  // freed inside the timing, like the checkpoint's
  }
}

/// Wall time of `work` on all ranks (barriers before and after).
double timed(MPI_Comm comm, const std::function<void()>& work) {
  MPI_Barrier(comm);
  const auto t0 = std::chrono::steady_clock::now();
  work();
  MPI_Barrier(comm);
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void removeFile(const fs::path& path, MPI_Comm comm) {
  MPI_Barrier(comm);
  if (mpi::rank(comm) == 0) fs::remove(path);
  MPI_Barrier(comm);
}

struct Times {
  std::vector<double> write, raw_write, raw_write_noflush, read, raw_read;
};

double best(const std::vector<double>& v) {
  return *std::min_element(v.begin(), v.end());
}
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

/// The benchmark's own directory: a new one, polydem_bench_checkpoint.<rank 0's pid>, inside
/// `parent` (made if missing). remove() deletes only what the benchmark wrote there, then that
/// directory, then `parent` if the benchmark made it and it is empty: files that were there before
/// are never touched (`--dir .` must not wipe the working directory).
class WorkDirectory {
 public:
  WorkDirectory(const fs::path& parent, MPI_Comm comm) {
    std::string path, error;
    if (mpi::rank(comm) == 0) {
      std::error_code ec;
      made_parent_ = !fs::exists(parent, ec) && fs::create_directories(parent, ec);
      path = (parent / ("polydem_bench_checkpoint." + std::to_string(getpid()))).string();
      if (ec) {
        error = "cannot create " + parent.string() + ": " + ec.message();
      } else if (!fs::create_directory(path, ec)) {  // false: it existed, so it is not ours
        error = "cannot create a new directory " + path + (ec ? ": " + ec.message() : ": exists");
      }
    }
    path_ = broadcast(path, comm);
    error = broadcast(error, comm);
    if (!error.empty()) throw Error("bench checkpoint: " + error);
    parent_ = parent;
    MPI_Barrier(comm);
  }
  const std::string& path() const { return path_; }

  void remove(MPI_Comm comm) const {
    MPI_Barrier(comm);
    if (mpi::rank(comm) != 0) return;
    std::error_code ec;
    for (const char* name : {"checkpoint.h5", "raw.h5"}) fs::remove(fs::path(path_) / name, ec);
    fs::remove(path_, ec);  // only if empty: never recursive
    if (made_parent_) fs::remove(parent_, ec);
  }

 private:
  static std::string broadcast(std::string text, MPI_Comm comm) {
    std::uint64_t length = text.size();
    MPI_Bcast(&length, 1, MPI_UINT64_T, 0, comm);
    text.resize(length);
    MPI_Bcast(text.data(), static_cast<int>(length), MPI_CHAR, 0, comm);
    return text;
  }

  std::string path_;
  fs::path parent_;
  bool made_parent_ = false;
};

}  // namespace

int benchCheckpoint(int argc, char** argv) {
  Args args(argc, argv, {"help", "keep"});
  if (args.flag("help")) {
    std::printf(
        "usage: mpirun -n P polydem bench checkpoint [--particles 100000,1000000]\n"
        "         [--histories-per-particle 6] [--repeat 3] [--round-mib 8] [--dir DIR]\n"
        "         [--json FILE] [--keep]\n"
        "  writes and reads a checkpoint of N particles (and 6 N pair histories) on the P\n"
        "  launched ranks, and the same bytes with plain parallel HDF5, and prints times,\n"
        "  bandwidths (payload bytes / wall time, best of --repeat) and their ratios.\n"
        "  The files go to a new directory polydem_bench_checkpoint.<pid> inside DIR (default:\n"
        "  the working directory); the benchmark deletes only the files it wrote there and that\n"
        "  directory (and DIR itself if it created DIR and DIR is empty). --keep keeps the last\n"
        "  checkpoint file and its directory.\n");
    return 0;
  }
  const auto counts = args.integers("particles", "100000,1000000", 1, Args::kInt64Max);
  const int per_particle = static_cast<int>(args.integer("histories-per-particle", 6, 0));
  const int repeat = static_cast<int>(args.integer("repeat", 3, 1));
  const auto json_path = args.value("json");
  const bool keep = args.flag("keep");
  hdf5::CheckpointIoOptions options;
  // A round of at least one byte and at most a TiB (a size_t holds it).
  options.round_bytes = static_cast<std::size_t>(
      args.number("round-mib", static_cast<double>(options.round_bytes) / (1 << 20),
                  1.0 / (1 << 20), 1 << 20) *
      (1 << 20));
  const std::string parent = args.value("dir", ".");
  args.rejectUnknown();
  const MPI_Comm comm = MPI_COMM_WORLD;
  const int rank = mpi::rank(comm), ranks = mpi::size(comm);
  const WorkDirectory work(parent, comm);
  const std::string& dir = work.path();

  if (rank == 0) {
    std::printf(
        "checkpoint bench: %d rank%s, best of %d, payload = particle and pair fields, "
        "directory %s\n",
        ranks, ranks > 1 ? "s" : "", repeat, dir.c_str());
    std::printf("%10s %9s %8s | %9s %8s %9s %8s %6s %9s %8s | %9s %8s %9s %8s %6s\n", "particles",
                "pairs", "MB", "write s", "GB/s", "raw s", "GB/s", "ratio", "raw-nf s", "GB/s",
                "read s", "GB/s", "raw s", "GB/s", "ratio");
  }
  nlohmann::json out = {{"ranks", ranks},
                        {"repeat", repeat},
                        {"directory", dir},
                        {"histories_per_particle", per_particle},
                        {"results", nlohmann::json::array()}};
  for (const std::int64_t n : counts) {
    Sample s = makeSample(n, per_particle, comm);
    const fs::path checkpoint = fs::path(dir) / "checkpoint.h5", raw = fs::path(dir) / "raw.h5";
    Times t;
    std::uint64_t file_bytes = 0;
    for (int k = 0; k < repeat; ++k) {
      t.write.push_back(
          timed(comm, [&] { checkpoint::writeCheckpoint(checkpoint, s.data, comm, options); }));
      t.raw_write.push_back(timed(comm, [&] { rawWrite(raw, s, comm, true); }));
      t.read.push_back(
          timed(comm, [&] { (void)checkpoint::readCheckpoint(checkpoint, comm, options); }));
      t.raw_read.push_back(timed(comm, [&] { rawRead(raw, s, comm); }));
      removeFile(raw, comm);
      t.raw_write_noflush.push_back(timed(comm, [&] { rawWrite(raw, s, comm, false); }));
      if (rank == 0) file_bytes = fs::file_size(checkpoint);
      removeFile(raw, comm);
      if (!keep || k + 1 < repeat) removeFile(checkpoint, comm);
    }
    const double gb = static_cast<double>(s.payload_bytes) / 1e9;
    const double w = best(t.write), rw = best(t.raw_write), rn = best(t.raw_write_noflush);
    const double r = best(t.read), rr = best(t.raw_read);
    if (rank == 0) {
      std::printf(
          "%10lld %9llu %8.1f | %9.3f %8.2f %9.3f %8.2f %5.0f%% %9.3f %8.2f | %9.3f %8.2f "
          "%9.3f %8.2f %5.0f%%\n",
          static_cast<long long>(n), static_cast<unsigned long long>(s.pairs), gb * 1e3, w, gb / w,
          rw, gb / rw, 100 * rw / w, rn, gb / rn, r, gb / r, rr, gb / rr, 100 * rr / r);
      std::fflush(stdout);
    }
    out["results"].push_back({{"particles", n},
                              {"pairs", s.pairs},
                              {"payload_bytes", s.payload_bytes},
                              {"checkpoint_file_bytes", file_bytes},
                              {"write_s", t.write},
                              {"raw_write_s", t.raw_write},
                              {"raw_write_noflush_s", t.raw_write_noflush},
                              {"read_s", t.read},
                              {"raw_read_s", t.raw_read},
                              {"write_gb_per_s_best", gb / w},
                              {"raw_write_gb_per_s_best", gb / rw},
                              {"write_ratio_best", rw / w},
                              {"write_ratio_median", median(t.raw_write) / median(t.write)},
                              {"read_gb_per_s_best", gb / r},
                              {"raw_read_gb_per_s_best", gb / rr},
                              {"read_ratio_best", rr / r},
                              {"read_ratio_median", median(t.raw_read) / median(t.read)}});
  }
  if (rank == 0) {
    std::printf(
        "ratio = raw HDF5 time / checkpoint time (100%%: as fast as the peer). raw: same "
        "bytes, flushed like the checkpoint; raw-nf: not flushed. Reads follow the writes "
        "and may come from the page cache.\n");
    if (json_path) {
      std::ofstream(*json_path) << out.dump(2) << "\n";
      std::printf("written: %s\n", json_path->c_str());
    }
    if (keep) std::printf("kept: %s\n", (fs::path(dir) / "checkpoint.h5").c_str());
  }
  if (!keep) work.remove(comm);
  return 0;
}

}  // namespace polydem::app

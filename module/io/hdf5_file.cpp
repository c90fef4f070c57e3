#include "io/hdf5_file.h"

#include <algorithm>
#include <cstring>

#include "core/error.h"
#include "core/state_hash.h"
#include "core/strings.h"
#include "io/checkpoint_checksum.h"

namespace polydem::io::h5 {

namespace {

// Memory type (native) and file type (explicit little-endian) of each element type.
template <typename T>
struct Type;
template <>
struct Type<double> {
  static hid_t mem() { return H5T_NATIVE_DOUBLE; }
  static hid_t file() { return H5T_IEEE_F64LE; }
  static constexpr const char* kName = "64-bit float";
};
template <>
struct Type<std::uint64_t> {
  static hid_t mem() { return H5T_NATIVE_UINT64; }
  static hid_t file() { return H5T_STD_U64LE; }
  static constexpr const char* kName = "64-bit unsigned integer";
};
template <>
struct Type<std::int64_t> {
  static hid_t mem() { return H5T_NATIVE_INT64; }
  static hid_t file() { return H5T_STD_I64LE; }
  static constexpr const char* kName = "64-bit integer";
};
template <>
struct Type<std::uint32_t> {
  static hid_t mem() { return H5T_NATIVE_UINT32; }
  static hid_t file() { return H5T_STD_U32LE; }
  static constexpr const char* kName = "32-bit unsigned integer";
};
template <>
struct Type<std::int32_t> {
  static hid_t mem() { return H5T_NATIVE_INT32; }
  static hid_t file() { return H5T_STD_I32LE; }
  static constexpr const char* kName = "32-bit integer";
};
template <>
struct Type<std::uint8_t> {
  static hid_t mem() { return H5T_NATIVE_UINT8; }
  static hid_t file() { return H5T_STD_U8LE; }
  static constexpr const char* kName = "8-bit unsigned integer";
};

/// Throws CheckpointError(what + ": " + HDF5's message) if `id` (an hid_t or herr_t) is negative.
template <typename Id>
Id check(Id id, const std::string& what) {
  if (id < 0) throw CheckpointError(what + ": " + hdf5ErrorMessage());
  return id;
}

herr_t walkError(unsigned, const H5E_error2_t* e, void* out) {
  auto& messages = *static_cast<std::vector<std::string>*>(out);
  if (e->desc && *e->desc) messages.emplace_back(e->desc);
  return 0;
}

std::string describeType(hid_t type) {
  const H5T_class_t cls = H5Tget_class(type);
  const std::size_t size = H5Tget_size(type);
  switch (cls) {
    case H5T_INTEGER:
      return cat(8 * size, "-bit ", H5Tget_sign(type) == H5T_SGN_NONE ? "unsigned " : "", "integer",
                 H5Tget_order(type) == H5T_ORDER_BE ? " (big-endian)" : "");
    case H5T_FLOAT:
      return cat(8 * size, "-bit float", H5Tget_order(type) == H5T_ORDER_BE ? " (big-endian)" : "");
    case H5T_STRING:
      return H5Tis_variable_str(type) > 0 ? "variable-length string" : "fixed-length string";
    default:
      return cat("HDF5 type class ", static_cast<int>(cls));
  }
}

std::string describeDims(const std::vector<std::uint64_t>& dims) {
  if (dims.empty()) return "a scalar";
  std::vector<std::string> parts;
  for (auto d : dims) parts.push_back(cat(d));
  return join(parts, " x ");
}

std::vector<std::uint64_t> spaceDims(hid_t space) {
  const int n = H5Sget_simple_extent_ndims(space);
  if (n < 0) throw CheckpointError("cannot read dimensions: " + hdf5ErrorMessage());
  std::vector<hsize_t> d(static_cast<std::size_t>(n));
  if (n > 0) H5Sget_simple_extent_dims(space, d.data(), nullptr);
  return {d.begin(), d.end()};
}

Handle stringType(std::size_t size) {
  Handle t(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(t.get(), std::max<std::size_t>(size, 1));
  H5Tset_strpad(t.get(), H5T_STR_NULLPAD);
  return t;
}

/// A memory space of `n` elements, or one element with nothing selected when n == 0 (the way a
/// rank takes part in a collective transfer without data).
Handle memorySpace(std::uint64_t n) {
  const hsize_t dim = std::max<std::uint64_t>(n, 1);
  Handle space(H5Screate_simple(1, &dim, nullptr), H5Sclose);
  if (n == 0) H5Sselect_none(space.get());
  return space;
}

std::uint64_t allreduceSum(std::uint64_t value, MPI_Comm comm) {
  std::uint64_t total = 0;
  MPI_Allreduce(&value, &total, 1, MPI_UINT64_T, MPI_SUM, comm);  // wraps mod 2^64
  return total;
}

}  // namespace

// --- handles and errors -----------------------------------------------------------------------

Handle& Handle::operator=(Handle&& other) noexcept {
  if (this != &other) {
    reset();
    id_ = other.id_;
    closer_ = other.closer_;
    other.id_ = -1;
  }
  return *this;
}

void Handle::reset() {
  if (id_ >= 0 && closer_) closer_(id_);
  id_ = -1;
}

ErrorSilencer::ErrorSilencer() {
  H5Eget_auto2(H5E_DEFAULT, &function_, &data_);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

ErrorSilencer::~ErrorSilencer() {
  H5Eset_auto2(H5E_DEFAULT, function_, data_);
}

std::string hdf5ErrorMessage() {
  std::vector<std::string> messages;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, walkError, &messages);
  H5Eclear2(H5E_DEFAULT);
  if (messages.empty()) return "HDF5 error";
  if (messages.size() == 1) return messages.front();
  return messages.front() + " (" + messages.back() + ")";
}

void agree(const std::optional<std::string>& error, MPI_Comm comm) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  const int mine = error ? rank : ranks;
  int first = ranks;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm);
  if (first == ranks) return;
  std::string message = rank == first ? *error : std::string();
  std::uint64_t length = message.size();
  MPI_Bcast(&length, 1, MPI_UINT64_T, first, comm);
  message.resize(length);
  MPI_Bcast(message.data(), static_cast<int>(length), MPI_CHAR, first, comm);
  throw CheckpointError(message);
}

// --- slices -----------------------------------------------------------------------------------

Slice writerSlice(std::uint64_t rows, MPI_Comm comm) {
  Slice s;
  s.rows = rows;
  MPI_Exscan(&rows, &s.offset, 1, MPI_UINT64_T, MPI_SUM, comm);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  if (rank == 0) s.offset = 0;  // MPI_Exscan leaves rank 0's result undefined
  s.total = allreduceSum(rows, comm);
  MPI_Allreduce(&rows, &s.max_rows, 1, MPI_UINT64_T, MPI_MAX, comm);
  return s;
}

Slice readerSlice(std::uint64_t total, int rank, int ranks) {
  const auto p = static_cast<std::uint64_t>(ranks), r = static_cast<std::uint64_t>(rank);
  const std::uint64_t base = total / p, extra = total % p;
  Slice s;
  s.total = total;
  s.rows = base + (r < extra ? 1 : 0);
  s.offset = r * base + std::min(r, extra);
  s.max_rows = base + (extra > 0 ? 1 : 0);
  return s;
}

Slice wholeSlice(std::uint64_t total) {
  return {0, total, total, total, true};
}

// --- file -------------------------------------------------------------------------------------

File::File(std::string name, MPI_Comm comm, const CheckpointIoOptions& options, bool writable)
    : name_(std::move(name)), comm_(comm), options_(options), writable_(writable) {
  MPI_Comm_rank(comm, &rank_);
}

File::~File() {
  transfer_.reset();
  file_.reset();  // collective; every rank unwinds through here at the same point
}

std::string File::context(const std::string& what) const {
  return "checkpoint " + name_ + ": " + what;
}

namespace {

Handle accessList(MPI_Comm comm) {
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  check(H5Pset_fapl_mpio(fapl.get(), comm, MPI_INFO_NULL), "cannot select MPI-IO");
  // Version 2 object headers carry checksums, so HDF5 itself detects damaged metadata.
  check(H5Pset_libver_bounds(fapl.get(), H5F_LIBVER_V18, H5F_LIBVER_LATEST),
        "cannot set format bounds");
  check(H5Pset_all_coll_metadata_ops(fapl.get(), true), "cannot set collective metadata reads");
  check(H5Pset_coll_metadata_write(fapl.get(), true), "cannot set collective metadata writes");
  return fapl;
}

Handle collectiveTransfer() {
  Handle dxpl(H5Pcreate(H5P_DATASET_XFER), H5Pclose);
  check(H5Pset_dxpl_mpio(dxpl.get(), H5FD_MPIO_COLLECTIVE), "cannot select collective transfers");
  return dxpl;
}

}  // namespace

File File::create(const std::filesystem::path& path, MPI_Comm comm,
                  const CheckpointIoOptions& options) {
  File f(path.string(), comm, options, true);
  std::optional<std::string> error;
  try {
    Handle fapl = accessList(comm);
    f.file_ = Handle(check(H5Fcreate(f.name_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()),
                           f.context("cannot create the file")),
                     H5Fclose);
    f.transfer_ = collectiveTransfer();
  } catch (const CheckpointError& e) {
    error = e.what();
  }
  agree(error, comm);
  return f;
}

File File::open(const std::filesystem::path& path, MPI_Comm comm,
                const CheckpointIoOptions& options) {
  File f(path.string(), comm, options, false);
  std::optional<std::string> error;
  try {
    if (!std::filesystem::is_regular_file(path)) {
      throw CheckpointError(f.context("no such file"));
    }
    Handle fapl = accessList(comm);
    f.file_ = Handle(check(H5Fopen(f.name_.c_str(), H5F_ACC_RDONLY, fapl.get()),
                           f.context("not a readable HDF5 file (truncated or damaged?)")),
                     H5Fclose);
    f.transfer_ = collectiveTransfer();
  } catch (const CheckpointError& e) {
    error = e.what();
  }
  agree(error, comm);
  return f;
}

void File::close() {
  std::optional<std::string> error;
  transfer_.reset();
  if (file_.get() >= 0) {
    if (writable_ && H5Fflush(file_.get(), H5F_SCOPE_GLOBAL) < 0) {
      error = context("cannot flush the file: " + hdf5ErrorMessage());
    }
    const hid_t id = file_.release();
    if (H5Fclose(id) < 0 && !error) error = context("cannot close the file: " + hdf5ErrorMessage());
  }
  agree(error, comm_);
}

bool File::exists(const std::string& path) const {
  // H5Lexists fails (rather than answering no) when an intermediate group is missing: walk down.
  std::size_t pos = 0;
  while (pos != std::string::npos) {
    pos = path.find('/', pos + 1);
    const std::string prefix = path.substr(0, pos);
    if (H5Lexists(file_.get(), prefix.c_str(), H5P_DEFAULT) <= 0) {
      H5Eclear2(H5E_DEFAULT);
      return false;
    }
  }
  return true;
}

Handle File::openDataset(const std::string& dataset) const {
  if (!exists(dataset)) throw CheckpointError(context("dataset " + dataset + " is missing"));
  return Handle(check(H5Dopen2(file_.get(), dataset.c_str(), H5P_DEFAULT),
                      context("cannot open dataset " + dataset)),
                H5Dclose);
}

void File::transfer(bool writing, hid_t dataset, hid_t mem_type, void* buffer,
                    std::size_t row_bytes, std::size_t cols, const Slice& slice) const {
  if (slice.total == 0) return;  // nothing allocated: HDF5 refuses even an empty transfer
  const std::uint64_t per_round =
      std::max<std::uint64_t>(1, options_.max_transfer_bytes / std::max<std::size_t>(row_bytes, 1));
  const std::uint64_t rounds = (slice.max_rows + per_round - 1) / per_round;
  Handle file_space(check(H5Dget_space(dataset), "cannot get a dataspace"), H5Sclose);
  std::optional<std::string> error;
  // Every rank makes the same number of collective calls, even after a failure of its own, so
  // that the others are not left waiting; the error is reported after the last round.
  for (std::uint64_t k = 0; k < rounds; ++k) {
    const std::uint64_t begin = k * per_round;
    const std::uint64_t n = slice.rows > begin ? std::min(per_round, slice.rows - begin) : 0;
    if (n > 0) {
      const hsize_t start[2] = {slice.offset + begin, 0};
      const hsize_t count[2] = {n, cols};
      H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, count, nullptr);
    } else {
      H5Sselect_none(file_space.get());
    }
    Handle mem_space = memorySpace(n * cols);
    // HDF5 refuses a null buffer even with nothing selected (an empty vector's data()).
    std::uint64_t dummy = 0;
    void* at = n > 0 ? static_cast<void*>(static_cast<unsigned char*>(buffer) + begin * row_bytes)
                     : static_cast<void*>(&dummy);
    const herr_t status =
        writing
            ? H5Dwrite(dataset, mem_type, mem_space.get(), file_space.get(), transfer_.get(), at)
            : H5Dread(dataset, mem_type, mem_space.get(), file_space.get(), transfer_.get(), at);
    if (status < 0 && !error) error = hdf5ErrorMessage();
  }
  if (error) throw CheckpointError(*error);
}

// --- writing ----------------------------------------------------------------------------------

void File::createGroup(const std::string& group, const std::string& description) {
  std::optional<std::string> error;
  try {
    Handle g(check(H5Gcreate2(file_.get(), group.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                   context("cannot create group " + group)),
             H5Gclose);
  } catch (const CheckpointError& e) {
    error = e.what();
  }
  agree(error, comm_);
  if (!description.empty()) writeAttribute(group, "description", description);
}

template <typename T>
void File::write(const std::string& dataset, std::span<const T> local, std::size_t cols,
                 const Slice& slice, const Info& info) {
  Handle d;
  std::optional<std::string> error;
  try {
    if (local.size() != slice.rows * cols) {
      throw CheckpointError(context(cat("dataset ", dataset, ": ", local.size(),
                                        " values given for ", slice.rows, " rows of ", cols)));
    }
    const hsize_t dims[2] = {slice.total, cols};
    Handle space(check(H5Screate_simple(cols > 1 ? 2 : 1, dims, nullptr),
                       context("dataset " + dataset + ": cannot create its dataspace")),
                 H5Sclose);
    Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
    // Every byte is written: skip HDF5's fill pass, which would write the data twice.
    H5Pset_fill_time(dcpl.get(), H5D_FILL_TIME_NEVER);
    H5Pset_alloc_time(dcpl.get(), H5D_ALLOC_TIME_EARLY);
    d = Handle(check(H5Dcreate2(file_.get(), dataset.c_str(), Type<T>::file(), space.get(),
                                H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
                     context("cannot create dataset " + dataset)),
               H5Dclose);
    try {
      transfer(true, d.get(), Type<T>::mem(), const_cast<T*>(local.data()), sizeof(T) * cols, cols,
               slice);
    } catch (const CheckpointError& e) {
      throw CheckpointError(context("cannot write dataset " + dataset + ": " + e.what()));
    }
  } catch (const CheckpointError& e) {
    error = e.what();
  }
  finishWrite(dataset, checksumPartial(local, slice.offset * cols), slice.total * cols, info,
              error);
}

void File::finishWrite(const std::string& dataset, std::uint64_t partial, std::uint64_t elements,
                       const Info& info, std::optional<std::string> error) {
  agree(error, comm_);
  const std::uint64_t checksum = checksumFinish(allreduceSum(partial, comm_), elements);
  writeAttribute(dataset, "checksum", checksum);
  if (!info.units.empty()) writeAttribute(dataset, "units", info.units);
  if (!info.description.empty()) writeAttribute(dataset, "description", info.description);
}

void File::writeStrings(const std::string& dataset, const std::vector<std::string>& values,
                        const Info& info) {
  std::size_t width = 1;
  for (const auto& v : values) width = std::max(width, v.size());
  const std::uint64_t count = values.size();
  std::vector<char> bytes;
  if (rank_ == 0) {
    bytes.assign(count * width, '\0');
    for (std::size_t i = 0; i < count; ++i) {
      std::memcpy(bytes.data() + i * width, values[i].data(), values[i].size());
    }
  }
  const Slice slice = writerSlice(rank_ == 0 ? count : 0, comm_);
  Handle d;
  std::optional<std::string> error;
  try {
    Handle type = stringType(width);
    const hsize_t dim = count;
    Handle space(H5Screate_simple(1, &dim, nullptr), H5Sclose);
    d = Handle(check(H5Dcreate2(file_.get(), dataset.c_str(), type.get(), space.get(), H5P_DEFAULT,
                                H5P_DEFAULT, H5P_DEFAULT),
                     context("cannot create dataset " + dataset)),
               H5Dclose);
    transfer(true, d.get(), type.get(), bytes.data(), width, 1, slice);
  } catch (const CheckpointError& e) {
    error = e.what();
  }
  finishWrite(dataset, checksumPartial(bytes.data(), bytes.size(), 1, 0), count * width, info,
              error);
}

void File::writeText(const std::string& dataset, const std::string& text, const Info& info) {
  const std::size_t width = std::max<std::size_t>(text.size(), 1);
  std::vector<char> bytes(width, '\0');
  std::memcpy(bytes.data(), text.data(), text.size());
  Handle d;
  std::optional<std::string> error;
  try {
    Handle type = stringType(width);
    Handle space(H5Screate(H5S_SCALAR), H5Sclose);
    d = Handle(check(H5Dcreate2(file_.get(), dataset.c_str(), type.get(), space.get(), H5P_DEFAULT,
                                H5P_DEFAULT, H5P_DEFAULT),
                     context("cannot create dataset " + dataset)),
               H5Dclose);
    Handle file_space(H5Dget_space(d.get()), H5Sclose);
    Handle mem_space(H5Screate(H5S_SCALAR), H5Sclose);
    if (rank_ != 0) {  // rank 0 writes the text; the others take part in the collective call
      H5Sselect_none(file_space.get());
      H5Sselect_none(mem_space.get());
    }
    check(H5Dwrite(d.get(), type.get(), mem_space.get(), file_space.get(), transfer_.get(),
                   bytes.data()),
          context("cannot write dataset " + dataset));
  } catch (const CheckpointError& e) {
    error = e.what();
  }
  const std::uint64_t partial = rank_ == 0 ? checksumPartial(bytes.data(), width, 1, 0) : 0;
  finishWrite(dataset, partial, width, info, error);
  writeAttribute<std::uint64_t>(dataset, "length", text.size());
}

void File::writeAttributeRaw(const std::string& object, const std::string& attribute,
                             hid_t file_type, hid_t mem_type, std::size_t count,
                             const void* values) {
  std::optional<std::string> error;
  try {
    const std::string what = "attribute " + attribute + " of " + object;
    Handle obj(
        check(H5Oopen(file_.get(), object.c_str(), H5P_DEFAULT), context("cannot open " + object)),
        H5Oclose);
    const hsize_t dim = count;
    Handle space(count == 1 ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, &dim, nullptr), H5Sclose);
    Handle a(check(H5Acreate2(obj.get(), attribute.c_str(), file_type, space.get(), H5P_DEFAULT,
                              H5P_DEFAULT),
                   context("cannot create " + what)),
             H5Aclose);
    check(H5Awrite(a.get(), mem_type, values), context("cannot write " + what));
  } catch (const CheckpointError& e) {
    error = e.what();
  }
  agree(error, comm_);
}

template <typename T>
void File::writeAttribute(const std::string& object, const std::string& attribute,
                          std::span<const T> values) {
  writeAttributeRaw(object, attribute, Type<T>::file(), Type<T>::mem(), values.size(),
                    values.data());
}

void File::writeAttribute(const std::string& object, const std::string& attribute,
                          const std::string& text) {
  Handle type = stringType(text.size());
  std::vector<char> bytes(std::max<std::size_t>(text.size(), 1), '\0');
  std::memcpy(bytes.data(), text.data(), text.size());
  writeAttributeRaw(object, attribute, type.get(), type.get(), 1, bytes.data());
}

// --- reading ----------------------------------------------------------------------------------

std::vector<std::uint64_t> File::dims(const std::string& dataset) const {
  std::optional<std::string> error;
  std::vector<std::uint64_t> out;
  try {
    Handle d = openDataset(dataset);
    Handle space(check(H5Dget_space(d.get()), context("dataset " + dataset)), H5Sclose);
    out = spaceDims(space.get());
  } catch (const CheckpointError& e) {
    error = e.what();
  }
  agree(error, comm_);
  return out;
}

void File::verify(const std::string& dataset, std::uint64_t partial, std::uint64_t elements,
                  bool sum_over_ranks, std::vector<std::uint64_t> dims,
                  std::optional<std::string> error) {
  agree(error, comm_);
  const std::uint64_t computed =
      checksumFinish(sum_over_ranks ? allreduceSum(partial, comm_) : partial, elements);
  std::uint64_t stored = 0;
  readAttributeRaw(dataset, "checksum", H5T_STD_U64LE, H5T_NATIVE_UINT64, 1, &stored);
  if (stored != computed) {
    error = context("dataset " + dataset + " is corrupted: its checksum is " +
                    BitHasher::hex(stored) + " but its data hash to " + BitHasher::hex(computed));
  }
  agree(error, comm_);
  datasets_.push_back({dataset, std::move(dims), stored});
}

template <typename T>
std::vector<T> File::read(const std::string& dataset, std::size_t cols, const Slice& slice,
                          std::uint64_t prefix) {
  std::vector<T> out((prefix + slice.rows) * cols);
  Handle d;
  std::vector<std::uint64_t> found;
  std::optional<std::string> error;
  try {
    d = openDataset(dataset);
    Handle type(H5Dget_type(d.get()), H5Tclose);
    if (H5Tequal(type.get(), Type<T>::file()) <= 0) {
      throw CheckpointError(context("dataset " + dataset + " holds " + describeType(type.get()) +
                                    " values, expected " + Type<T>::kName));
    }
    Handle space(check(H5Dget_space(d.get()), context("dataset " + dataset)), H5Sclose);
    found = spaceDims(space.get());
    const std::vector<std::uint64_t> expected = cols > 1
                                                    ? std::vector<std::uint64_t>{slice.total, cols}
                                                    : std::vector<std::uint64_t>{slice.total};
    if (found != expected) {
      throw CheckpointError(context("dataset " + dataset + " has shape " + describeDims(found) +
                                    ", expected " + describeDims(expected) +
                                    " (inconsistent sizes)"));
    }
    try {
      if (prefix > 0) {
        transfer(false, d.get(), Type<T>::mem(), out.data(), sizeof(T) * cols, cols,
                 Slice{0, prefix, slice.total, prefix, true});
      }
      transfer(false, d.get(), Type<T>::mem(), out.data() + prefix * cols, sizeof(T) * cols, cols,
               slice);
    } catch (const CheckpointError& e) {
      throw CheckpointError(context("cannot read dataset " + dataset + ": " + e.what()));
    }
  } catch (const CheckpointError& e) {
    error = e.what();
  }
  // Rows read by every rank count once (rank 0's copy), this rank's own slice once.
  const std::span<const T> all(out);
  std::uint64_t partial = checksumPartial(all.subspan(prefix * cols), slice.offset * cols);
  if (rank_ == 0 || slice.replicated) partial += checksumPartial(all.first(prefix * cols), 0);
  verify(dataset, partial, slice.total * cols, !slice.replicated, found, error);
  return out;
}

std::vector<std::string> File::readStrings(const std::string& dataset, std::uint64_t count) {
  std::vector<char> bytes;
  std::size_t width = 1;
  std::vector<std::uint64_t> found;
  Handle d;
  std::optional<std::string> error;
  try {
    d = openDataset(dataset);
    Handle type(H5Dget_type(d.get()), H5Tclose);
    if (H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) > 0) {
      throw CheckpointError(context("dataset " + dataset + " holds " + describeType(type.get()) +
                                    " values, expected fixed-length strings"));
    }
    width = H5Tget_size(type.get());
    Handle space(H5Dget_space(d.get()), H5Sclose);
    found = spaceDims(space.get());
    if (found != std::vector<std::uint64_t>{count}) {
      throw CheckpointError(context("dataset " + dataset + " has shape " + describeDims(found) +
                                    cat(", expected ", count, " (inconsistent sizes)")));
    }
    bytes.assign(count * width, '\0');
    Handle mem_type = stringType(width);
    transfer(false, d.get(), mem_type.get(), bytes.data(), width, 1, wholeSlice(count));
  } catch (const CheckpointError& e) {
    error = e.what();
  }
  verify(dataset, checksumPartial(bytes.data(), bytes.size(), 1, 0), count * width, false, found,
         error);
  std::vector<std::string> out(count);
  for (std::size_t i = 0; i < count; ++i) {
    const char* s = bytes.data() + i * width;
    out[i].assign(s, strnlen(s, width));
  }
  return out;
}

std::string File::readText(const std::string& dataset) {
  std::vector<char> bytes;
  Handle d;
  std::optional<std::string> error;
  try {
    d = openDataset(dataset);
    Handle type(H5Dget_type(d.get()), H5Tclose);
    Handle space(H5Dget_space(d.get()), H5Sclose);
    if (H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) > 0 ||
        H5Sget_simple_extent_type(space.get()) != H5S_SCALAR) {
      throw CheckpointError(context("dataset " + dataset + " is not a fixed-length string"));
    }
    bytes.assign(H5Tget_size(type.get()), '\0');
    Handle mem_type = stringType(bytes.size());
    check(H5Dread(d.get(), mem_type.get(), H5S_ALL, H5S_ALL, transfer_.get(), bytes.data()),
          context("cannot read dataset " + dataset));
  } catch (const CheckpointError& e) {
    error = e.what();
  }
  verify(dataset, checksumPartial(bytes.data(), bytes.size(), 1, 0), bytes.size(), false, {},
         error);
  const auto length = readAttribute<std::uint64_t>(dataset, "length");
  if (length > bytes.size()) {
    error = context(cat("dataset ", dataset, ": length ", length, " exceeds its ", bytes.size(),
                        " stored bytes"));
  }
  agree(error, comm_);
  return std::string(bytes.data(), length);
}

void File::readAttributeRaw(const std::string& object, const std::string& attribute,
                            hid_t file_type, hid_t mem_type, std::size_t count,
                            void* values) const {
  std::optional<std::string> error;
  try {
    const std::string what = "attribute " + attribute + " of " + object;
    if (object != "/" && !exists(object)) throw CheckpointError(context(object + " is missing"));
    if (H5Aexists_by_name(file_.get(), object.c_str(), attribute.c_str(), H5P_DEFAULT) <= 0) {
      H5Eclear2(H5E_DEFAULT);
      throw CheckpointError(context(what + " is missing"));
    }
    Handle a(check(H5Aopen_by_name(file_.get(), object.c_str(), attribute.c_str(), H5P_DEFAULT,
                                   H5P_DEFAULT),
                   context("cannot open " + what)),
             H5Aclose);
    Handle type(H5Aget_type(a.get()), H5Tclose);
    Handle space(H5Aget_space(a.get()), H5Sclose);
    const bool is_string = H5Tget_class(file_type) == H5T_STRING;
    const bool type_ok =
        is_string ? H5Tget_class(type.get()) == H5T_STRING && H5Tis_variable_str(type.get()) <= 0
                  : H5Tequal(type.get(), file_type) > 0;
    if (!type_ok) {
      throw CheckpointError(context(what + " holds " + describeType(type.get()) + " values"));
    }
    const auto points = H5Sget_simple_extent_npoints(space.get());
    if (points != static_cast<hssize_t>(count)) {
      throw CheckpointError(context(cat(what, " has ", points, " values, expected ", count)));
    }
    check(H5Aread(a.get(), mem_type, values), context("cannot read " + what));
  } catch (const CheckpointError& e) {
    error = e.what();
  }
  agree(error, comm_);
}

template <typename T>
std::vector<T> File::readAttribute(const std::string& object, const std::string& attribute,
                                   std::size_t count) {
  std::vector<T> out(count);
  readAttributeRaw(object, attribute, Type<T>::file(), Type<T>::mem(), count, out.data());
  return out;
}

std::string File::readStringAttribute(const std::string& object, const std::string& attribute) {
  // The width is the stored one: read the type first, then the bytes.
  std::size_t width = 0;
  std::optional<std::string> error;
  try {
    if (H5Aexists_by_name(file_.get(), object.c_str(), attribute.c_str(), H5P_DEFAULT) > 0) {
      Handle a(
          H5Aopen_by_name(file_.get(), object.c_str(), attribute.c_str(), H5P_DEFAULT, H5P_DEFAULT),
          H5Aclose);
      Handle type(H5Aget_type(a.get()), H5Tclose);
      width = H5Tget_size(type.get());
    }
    H5Eclear2(H5E_DEFAULT);
  } catch (const CheckpointError& e) {
    error = e.what();
  }
  agree(error, comm_);
  Handle type = stringType(std::max<std::size_t>(width, 1));
  std::vector<char> bytes(std::max<std::size_t>(width, 1), '\0');
  readAttributeRaw(object, attribute, type.get(), type.get(), 1, bytes.data());
  return std::string(bytes.data(), strnlen(bytes.data(), bytes.size()));
}

// --- instantiations -----------------------------------------------------------------------------

#define POLYDEM_H5_INSTANTIATE(T)                                                                 \
  template void File::write<T>(const std::string&, std::span<const T>, std::size_t, const Slice&, \
                               const Info&);                                                      \
  template std::vector<T> File::read<T>(const std::string&, std::size_t, const Slice&,            \
                                        std::uint64_t);                                           \
  template void File::writeAttribute<T>(const std::string&, const std::string&,                   \
                                        std::span<const T>);                                      \
  template std::vector<T> File::readAttribute<T>(const std::string&, const std::string&,          \
                                                 std::size_t);
POLYDEM_H5_INSTANTIATE(double)
POLYDEM_H5_INSTANTIATE(std::uint64_t)
POLYDEM_H5_INSTANTIATE(std::int64_t)
POLYDEM_H5_INSTANTIATE(std::uint32_t)
POLYDEM_H5_INSTANTIATE(std::int32_t)
POLYDEM_H5_INSTANTIATE(std::uint8_t)
#undef POLYDEM_H5_INSTANTIATE

}  // namespace polydem::io::h5

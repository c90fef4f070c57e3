// The file, its attributes, errors, agreement and checksums; datasets are in hdf5_dataset.cpp.
#include "polydem/hdf5/hdf5_file.h"

#include <algorithm>
#include <cstring>

#include "polydem/core/error.h"
#include "polydem/core/file_kind.h"
#include "polydem/core/state_hash.h"
#include "polydem/core/strings.h"
#include "polydem/hdf5/checksum.h"
#include "polydem/hdf5/hdf5_types.h"
#include "polydem/hdf5/library.h"

namespace polydem::hdf5 {

namespace {

/// Disk space a writable file holds beyond the end of its last dataset's data (File::reserve):
/// room for the metadata HDF5 allocates after it (object headers, attributes, group entries; a
/// checkpoint's or snapshot's are a few kilobytes), which its flushes write.
constexpr std::uint64_t kSpaceAhead = std::uint64_t{128} << 10;

herr_t walkError(unsigned, const H5E_error2_t* e, void* out) {
  auto& messages = *static_cast<std::vector<std::string>*>(out);
  if (e->desc && *e->desc) messages.emplace_back(e->desc);
  return 0;
}

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

Handle transferList(H5FD_mpio_xfer_t mode) {
  Handle dxpl(H5Pcreate(H5P_DATASET_XFER), H5Pclose);
  check(H5Pset_dxpl_mpio(dxpl.get(), mode), "cannot set the transfer mode");
  return dxpl;
}

}  // namespace

// --- handles, types and errors ------------------------------------------------------------------

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

Handle stringType(std::size_t size) {
  Handle t(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(t.get(), std::max<std::size_t>(size, 1));
  H5Tset_strpad(t.get(), H5T_STR_NULLPAD);
  return t;
}

hid_t fileTypeOf(int code) {
  const hid_t types[] = {Type<double>::file(),       Type<std::uint64_t>::file(),
                         Type<std::int64_t>::file(), Type<std::uint32_t>::file(),
                         Type<std::int32_t>::file(), Type<std::uint8_t>::file()};
  return types[code];
}

hid_t memTypeOf(int code) {
  const hid_t types[] = {Type<double>::mem(),       Type<std::uint64_t>::mem(),
                         Type<std::int64_t>::mem(), Type<std::uint32_t>::mem(),
                         Type<std::int32_t>::mem(), Type<std::uint8_t>::mem()};
  return types[code];
}

int bytesOf(int code) {
  return code <= 2 ? 8 : code <= 4 ? 4 : 1;
}

std::string describeType(hid_t type) {
  const H5T_class_t cls = H5Tget_class(type);
  const std::size_t size = H5Tget_size(type);
  const char* order = H5Tget_order(type) == H5T_ORDER_BE ? " (big-endian)" : "";
  switch (cls) {
    case H5T_INTEGER:
      return cat(8 * size, "-bit ", H5Tget_sign(type) == H5T_SGN_NONE ? "unsigned " : "", "integer",
                 order);
    case H5T_FLOAT:
      return cat(8 * size, "-bit float", order);
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

// --- slices and rounds ------------------------------------------------------------------------

Slice writerSlice(std::uint64_t rows, MPI_Comm comm) {
  // One reduction gives the offset (sum over lower ranks), the total and the largest share.
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  std::vector<std::uint64_t> all(static_cast<std::size_t>(ranks));
  MPI_Allgather(&rows, 1, MPI_UINT64_T, all.data(), 1, MPI_UINT64_T, comm);
  Slice s;
  s.rows = rows;
  for (int r = 0; r < ranks; ++r) {
    if (r < rank) s.offset += all[r];
    s.total += all[r];
    s.max_rows = std::max(s.max_rows, all[r]);
  }
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

Rounds::Rounds(const Slice& slice, std::size_t row_bytes, std::size_t round_bytes)
    : per_round(std::max<std::uint64_t>(1, round_bytes / std::max<std::size_t>(row_bytes, 1))),
      rows(slice.rows) {
  count = (slice.max_rows + per_round - 1) / per_round;
}

// --- file -------------------------------------------------------------------------------------

File::File(std::string name, MPI_Comm comm, const CheckpointIoOptions& options, bool writable)
    : name_(name), path_(std::move(name)), comm_(comm), options_(options), writable_(writable) {
  MPI_Comm_rank(comm, &rank_);
}

File::~File() {
  collective_.reset();
  independent_.reset();
  if (writable_ && file_.get() >= 0) {
    // Not closed: an agreed error is unwinding, and the caller removes the file. Its blocks are
    // given back first, so that the metadata HDF5 still writes when it closes the file fits on
    // a full disk even where its space could not be taken ahead: a failed close would leave the
    // library in a state that crashes it at exit.
    if (rank_ == 0) space_.discard();
    MPI_Barrier(comm_);
  }
  space_.close();
  file_.reset();  // collective; every rank unwinds through here at the same point
}

std::string File::context(const std::string& what) const {
  return options_.kind + " " + name_ + ": " + what;
}

File File::create(const std::filesystem::path& path, MPI_Comm comm,
                  const CheckpointIoOptions& options, const std::string& shown_as) {
  File f(path.string(), comm, options, false);  // writable once created on every rank
  if (!shown_as.empty()) f.name_ = shown_as;
  std::optional<std::string> error;
  try {
    Handle fapl = accessList(comm);
    f.file_ = Handle(check(H5Fcreate(f.path_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()),
                           f.context("cannot create the file")),
                     H5Fclose);
    f.collective_ = transferList(H5FD_MPIO_COLLECTIVE);
    f.independent_ = transferList(H5FD_MPIO_INDEPENDENT);
  } catch (const CheckpointError& e) {
    error = e.what();
  }
  agree(error, comm);
  f.writable_ = true;
  // Rank 0 allocates the file's space (disk_space.h); where it cannot open the file for that,
  // the file is written without.
  int opened = f.rank_ == 0 ? f.space_.open(f.path_) : 0;  // kept open for ~File too
  MPI_Bcast(&opened, 1, MPI_INT, 0, comm);
  f.reserving_ = opened == 0;
  f.reserve();
  return f;
}

void File::reserve(hid_t dataset) {
  if (!writable_ || !reserving_) return;
  // HDF5 allocates in increasing addresses: a dataset's data at creation (H5D_ALLOC_TIME_EARLY),
  // metadata in small blocks as it goes. The end of the newest data is the same on every rank
  // (dataset creation is collective), and so is the decision below. (HDF5's own end of
  // allocation cannot be asked for with MPI-IO once a rank has written data.)
  if (dataset >= 0) {
    const haddr_t offset = H5Dget_offset(dataset);
    if (offset != HADDR_UNDEF) {
      data_end_ = std::max<std::uint64_t>(data_end_, offset + H5Dget_storage_size(dataset));
    }
    H5Eclear2(H5E_DEFAULT);  // no offset: a dataset without data
  }
  if (data_end_ + kSpaceAhead / 2 <= reserved_) return;
  const std::uint64_t target = data_end_ + kSpaceAhead;
  int code = rank_ == 0 ? space_.allocate(target) : 0;
  MPI_Bcast(&code, 1, MPI_INT, 0, comm_);
  if (code == 0) {
    reserved_ = target;
  } else if (cannotAllocateAhead(code)) {
    reserving_ = false;
  } else {
    std::optional<std::string> error;
    if (rank_ == 0) error = context(allocationFailure(code, target, directoryOf(path_)));
    agree(error, comm_);
  }
}

File File::open(const std::filesystem::path& path, MPI_Comm comm,
                const CheckpointIoOptions& options) {
  File f(path.string(), comm, options, false);
  std::optional<std::string> error;
  try {
    if (const std::string problem = notARegularFile(path.string()); !problem.empty()) {
      throw CheckpointError(f.context(problem));
    }
    Handle fapl = accessList(comm);
    f.file_ = Handle(check(H5Fopen(f.name_.c_str(), H5F_ACC_RDONLY, fapl.get()),
                           f.context("not a readable HDF5 file (truncated or damaged?)")),
                     H5Fclose);
    f.collective_ = transferList(H5FD_MPIO_COLLECTIVE);
    f.independent_ = transferList(H5FD_MPIO_INDEPENDENT);
  } catch (const CheckpointError& e) {
    error = e.what();
  }
  agree(error, comm);
  return f;
}

void File::close() {
  collective_.reset();
  independent_.reset();
  if (file_.get() < 0) return;
  std::optional<std::string> error;
  if (writable_ && options_.sync_on_close && H5Fflush(file_.get(), H5F_SCOPE_GLOBAL) < 0) {
    error =
        context("cannot flush the file: " + hdf5ErrorMessage() + freeSpaceNote(directoryOf(path_)));
  }
  space_.close();
  agree(error, comm_);  // a failed flush throws on every rank; ~File then closes the file
  const hid_t id = file_.release();
  if (H5Fclose(id) < 0) {
    error = context("cannot close the file: " + hdf5ErrorMessage() +
                    (writable_ ? freeSpaceNote(directoryOf(path_)) : std::string()));
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

FileDigest File::digest() const {
  return fileDigest(file_.get(), context(""));
}

void File::createGroup(const std::string& group, const std::string& description) {
  Handle g(check(H5Gcreate2(file_.get(), group.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                 context("cannot create group " + group)),
           H5Gclose);
  if (!description.empty()) writeAttribute(group, "description", description);
}

// --- checksums --------------------------------------------------------------------------------

void File::writeInfo(const std::string& dataset, std::uint64_t checksum, const Info& info) {
  writeAttribute(dataset, "checksum", checksum);
  if (!info.units.empty()) writeAttribute(dataset, "units", info.units);
  if (!info.description.empty()) writeAttribute(dataset, "description", info.description);
}

void File::verify(const std::string& dataset, std::uint64_t computed,
                  std::vector<std::uint64_t> dims) {
  const auto stored = readAttribute<std::uint64_t>(dataset, "checksum");
  if (stored != computed) {  // the same on every rank: both values are
    throw CheckpointError(context("dataset " + dataset + " is corrupted: its checksum is " +
                                  BitHasher::hex(stored) + " but its data hash to " +
                                  BitHasher::hex(computed)));
  }
  datasets_.push_back({dataset, std::move(dims), stored});
}

void File::finish(std::span<Dataset* const> datasets, bool replicated) {
  std::optional<std::string> error;
  std::vector<std::uint64_t> sums;
  for (const Dataset* d : datasets) {
    if (d->error_ && !error) {
      // MPI-IO does not say why a write failed; the free space tells the likeliest cause.
      error = *d->error_ + (d->writing_ ? freeSpaceNote(directoryOf(path_)) : std::string());
    }
    sums.push_back(d->partial_);
  }
  agree(error, comm_);
  if (!replicated) {  // wraps mod 2^64, as the checksum's sum does
    MPI_Allreduce(MPI_IN_PLACE, sums.data(), static_cast<int>(sums.size()), MPI_UINT64_T, MPI_SUM,
                  comm_);
  }
  for (std::size_t i = 0; i < datasets.size(); ++i) {
    Dataset& d = *datasets[i];
    const std::uint64_t checksum = checksumFinish(sums[i], d.total_ * d.cols_);
    if (d.writing_) {
      writeInfo(d.name_, checksum, d.info_);
    } else {
      verify(d.name_, checksum, d.dims_);
    }
  }
}

// --- attributes -------------------------------------------------------------------------------

void File::writeAttributeRaw(const std::string& object, const std::string& attribute,
                             hid_t file_type, hid_t mem_type, std::size_t count,
                             const void* values) {
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

void File::readAttributeRaw(const std::string& object, const std::string& attribute,
                            hid_t file_type, hid_t mem_type, std::size_t count,
                            void* values) const {
  const std::string what = "attribute " + attribute + " of " + object;
  if (object != "/" && !exists(object)) throw CheckpointError(context(object + " is missing"));
  const htri_t exists =
      H5Aexists_by_name(file_.get(), object.c_str(), attribute.c_str(), H5P_DEFAULT);
  if (exists < 0) {  // damaged metadata, e.g. an object header whose checksum fails
    throw CheckpointError(context("cannot read " + what + ": " + hdf5ErrorMessage()));
  }
  if (exists == 0) throw CheckpointError(context(what + " is missing"));
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
  if (H5Aexists_by_name(file_.get(), object.c_str(), attribute.c_str(), H5P_DEFAULT) > 0) {
    Handle a(
        H5Aopen_by_name(file_.get(), object.c_str(), attribute.c_str(), H5P_DEFAULT, H5P_DEFAULT),
        H5Aclose);
    Handle type(H5Aget_type(a.get()), H5Tclose);
    width = H5Tget_size(type.get());
  }
  H5Eclear2(H5E_DEFAULT);
  Handle type = stringType(std::max<std::size_t>(width, 1));
  std::vector<char> bytes(std::max<std::size_t>(width, 1), '\0');
  readAttributeRaw(object, attribute, type.get(), type.get(), 1, bytes.data());
  return std::string(bytes.data(), strnlen(bytes.data(), bytes.size()));
}

#define POLYDEM_H5_INSTANTIATE(T)                                                        \
  template void File::writeAttribute<T>(const std::string&, const std::string&,          \
                                        std::span<const T>);                             \
  template std::vector<T> File::readAttribute<T>(const std::string&, const std::string&, \
                                                 std::size_t);
POLYDEM_H5_INSTANTIATE(double)
POLYDEM_H5_INSTANTIATE(std::uint64_t)
POLYDEM_H5_INSTANTIATE(std::int64_t)
POLYDEM_H5_INSTANTIATE(std::uint32_t)
POLYDEM_H5_INSTANTIATE(std::int32_t)
POLYDEM_H5_INSTANTIATE(std::uint8_t)
#undef POLYDEM_H5_INSTANTIATE

}  // namespace polydem::hdf5

namespace polydem::hdf5 {

void closeHdf5Library() {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // H5_term_library reports only if printing is on
  H5close();
}

}  // namespace polydem::hdf5

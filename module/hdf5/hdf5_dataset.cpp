// Datasets: distributed ones created or opened once and moved in collective rounds of hyperslabs,
// replicated ones written from rank 0 in one batch and read whole by every rank; all checksummed.
#include <algorithm>
#include <cstring>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/hdf5/checksum.h"
#include "polydem/hdf5/hdf5_file.h"
#include "polydem/hdf5/hdf5_types.h"

namespace polydem::hdf5 {

namespace {

std::vector<std::uint64_t> spaceDims(hid_t space) {
  const int n = H5Sget_simple_extent_ndims(space);
  if (n < 0) throw CheckpointError("cannot read dimensions: " + hdf5ErrorMessage());
  std::vector<hsize_t> d(static_cast<std::size_t>(n));
  if (n > 0) H5Sget_simple_extent_dims(space, d.data(), nullptr);
  return {d.begin(), d.end()};
}

std::vector<std::uint64_t> shapeOf(std::uint64_t total, std::size_t cols) {
  return cols > 1 ? std::vector<std::uint64_t>{total, cols} : std::vector<std::uint64_t>{total};
}

/// Creation properties of every dataset: contiguous, allocated at once, never filled (every byte
/// is written; HDF5's fill pass would write the data twice).
Handle creationList() {
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  H5Pset_fill_time(dcpl.get(), H5D_FILL_TIME_NEVER);
  H5Pset_alloc_time(dcpl.get(), H5D_ALLOC_TIME_EARLY);
  return dcpl;
}

}  // namespace

// --- distributed datasets ---------------------------------------------------------------------

void Dataset::transfer(bool writing, void* data, std::uint64_t first_row, std::uint64_t rows) {
  if (total_ == 0) return;  // nothing allocated: HDF5 refuses even an empty transfer
  // A rank without rows still takes part, with empty selections (and a buffer HDF5 accepts).
  std::uint64_t dummy = 0;
  const hsize_t elements = std::max<hsize_t>(rows * cols_, 1);
  Handle mem_space(H5Screate_simple(1, &elements, nullptr), H5Sclose);
  if (rows > 0) {
    const hsize_t start[2] = {first_row, 0}, count[2] = {rows, cols_};
    H5Sselect_hyperslab(file_space_.get(), H5S_SELECT_SET, start, nullptr, count, nullptr);
  } else {
    H5Sselect_none(file_space_.get());
    H5Sselect_none(mem_space.get());
    data = &dummy;
  }
  const herr_t status =
      writing
          ? H5Dwrite(id_.get(), mem_type_, mem_space.get(), file_space_.get(), transfer_list_, data)
          : H5Dread(id_.get(), mem_type_, mem_space.get(), file_space_.get(), transfer_list_, data);
  // A failed round is remembered, not thrown: this rank must still take part in the next rounds.
  if (status < 0 && !error_) {
    error_ = context_ + "cannot " + (writing ? "write" : "read") + " dataset " + name_ + ": " +
             hdf5ErrorMessage();
  }
}

void Dataset::writeRuns(const void* data, std::span<const Run> runs) {
  std::uint64_t rows = 0;
  for (const Run& r : runs) rows += r.rows;
  if (total_ == 0) return;
  // The union of the runs' hyperslabs: HDF5 moves the selected rows in file order, which is the
  // order of the runs in `data`.
  std::uint64_t dummy = 0;
  const hsize_t elements = std::max<hsize_t>(rows * cols_, 1);
  Handle mem_space(H5Screate_simple(1, &elements, nullptr), H5Sclose);
  H5Sselect_none(file_space_.get());
  for (const Run& r : runs) {
    if (r.rows == 0) continue;
    const hsize_t start[2] = {r.first, 0}, count[2] = {r.rows, cols_};
    H5Sselect_hyperslab(file_space_.get(), H5S_SELECT_OR, start, nullptr, count, nullptr);
  }
  if (rows == 0) {
    H5Sselect_none(mem_space.get());
    data = &dummy;
  }
  if (H5Dwrite(id_.get(), mem_type_, mem_space.get(), file_space_.get(), transfer_list_, data) <
          0 &&
      !error_) {
    error_ = context_ + "cannot write dataset " + name_ + ": " + hdf5ErrorMessage();
  }
  const auto* bytes = static_cast<const std::byte*>(data);
  for (const Run& r : runs) {
    hash(bytes, r.first, r.rows);
    bytes += r.rows * cols_ * element_bytes_;
  }
}

void Dataset::write(const void* data, std::uint64_t first_row, std::uint64_t rows) {
  transfer(true, const_cast<void*>(data), first_row, rows);
}

void Dataset::read(void* data, std::uint64_t first_row, std::uint64_t rows) {
  transfer(false, data, first_row, rows);
}

void Dataset::hash(const void* data, std::uint64_t first_row, std::uint64_t rows) {
  partial_ +=
      checksumPartial(data, rows * cols_, static_cast<int>(element_bytes_), first_row * cols_);
}

template <typename T>
Dataset File::datasetOf(const std::string& dataset, std::uint64_t total, std::size_t cols) const {
  Dataset d;
  d.context_ = context("");
  d.name_ = dataset;
  d.transfer_list_ = collective_.get();
  d.mem_type_ = Type<T>::mem();
  d.element_bytes_ = sizeof(T);
  d.cols_ = cols;
  d.total_ = total;
  return d;
}

template <typename T>
Dataset File::create(const std::string& dataset, std::uint64_t total, std::size_t cols,
                     const Info& info) {
  Dataset d = datasetOf<T>(dataset, total, cols);
  d.info_ = info;
  d.writing_ = true;
  const hsize_t dims[2] = {total, cols};
  Handle space(check(H5Screate_simple(cols > 1 ? 2 : 1, dims, nullptr),
                     context("dataset " + dataset + ": cannot create its dataspace")),
               H5Sclose);
  Handle dcpl = creationList();
  d.id_ = Handle(check(H5Dcreate2(file_.get(), dataset.c_str(), Type<T>::file(), space.get(),
                                  H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
                       context("cannot create dataset " + dataset)),
                 H5Dclose);
  d.file_space_ = Handle(H5Dget_space(d.id_.get()), H5Sclose);
  reserve(d.id_.get());  // the data's blocks, before any rank writes there
  return d;
}

template <typename T>
Dataset File::open(const std::string& dataset, std::uint64_t total, std::size_t cols) {
  Dataset d = datasetOf<T>(dataset, total, cols);
  d.id_ = openDataset(dataset);
  Handle type(H5Dget_type(d.id_.get()), H5Tclose);
  if (H5Tequal(type.get(), Type<T>::file()) <= 0) {
    throw CheckpointError(context("dataset " + dataset + " holds " + describeType(type.get()) +
                                  " values, expected " + Type<T>::kName));
  }
  d.file_space_ = Handle(check(H5Dget_space(d.id_.get()), context("dataset " + dataset)), H5Sclose);
  d.dims_ = spaceDims(d.file_space_.get());
  if (d.dims_ != shapeOf(total, cols)) {
    throw CheckpointError(context("dataset " + dataset + " has shape " + describeDims(d.dims_) +
                                  ", expected " + describeDims(shapeOf(total, cols)) +
                                  " (inconsistent sizes)"));
  }
  return d;
}

// --- replicated datasets: writing
// -----------------------------------------------------------------

ReplicatedBatch::ReplicatedBatch(MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  rank0_ = rank == 0;
}

ReplicatedBatch::Item& ReplicatedBatch::add(const std::string& name, const Info& info, int kind) {
  items_.push_back({name, info, kind, 0, 1, 0, 0, {}});
  return items_.back();
}

template <typename T>
void ReplicatedBatch::table(const std::string& name, const std::vector<T>& values, std::size_t cols,
                            const Info& info) {
  Item& item = add(name, info, Type<T>::kCode);
  if (!rank0_) return;
  item.rows = values.size() / cols;
  item.cols = cols;
  const auto* bytes = reinterpret_cast<const std::byte*>(values.data());
  item.bytes.assign(bytes, bytes + values.size() * sizeof(T));
  item.checksum = checksumFinish(checksumPartial(std::span<const T>(values), 0), values.size());
}

void ReplicatedBatch::strings(const std::string& name, const std::vector<std::string>& values,
                              const Info& info) {
  Item& item = add(name, info, kStrings);
  if (!rank0_) return;
  std::size_t width = 1;
  for (const auto& v : values) width = std::max(width, v.size());
  item.rows = values.size();
  item.width = width;
  item.bytes.assign(values.size() * width, std::byte{0});
  for (std::size_t i = 0; i < values.size(); ++i) {
    std::memcpy(item.bytes.data() + i * width, values[i].data(), values[i].size());
  }
  item.checksum = checksumFinish(checksumPartial(item.bytes.data(), item.bytes.size(), 1, 0),
                                 item.bytes.size());
}

void ReplicatedBatch::text(const std::string& name, const std::string& text, const Info& info) {
  Item& item = add(name, info, kText);
  if (!rank0_) return;
  item.rows = text.size();  // the length; the stored string is padded to at least one byte
  item.width = std::max<std::size_t>(text.size(), 1);
  item.bytes.assign(item.width, std::byte{0});
  std::memcpy(item.bytes.data(), text.data(), text.size());
  item.checksum = checksumFinish(checksumPartial(item.bytes.data(), item.width, 1, 0), item.width);
}

void File::write(const ReplicatedBatch& batch) {
  // Rank 0's shapes and checksums, for the collective creation of the datasets and attributes.
  std::vector<std::uint64_t> shapes;
  for (const auto& item : batch.items_) {
    shapes.insert(shapes.end(), {item.rows, item.cols, item.width, item.checksum});
  }
  MPI_Bcast(shapes.data(), static_cast<int>(shapes.size()), MPI_UINT64_T, 0, comm_);
  std::optional<std::string> error;
  for (std::size_t i = 0; i < batch.items_.size(); ++i) {
    const auto& item = batch.items_[i];
    const std::uint64_t rows = shapes[4 * i], cols = shapes[4 * i + 1], width = shapes[4 * i + 2];
    Handle string_type;
    hid_t file_type = -1, mem_type = -1;
    Handle space;
    if (item.kind == kText) {
      string_type = stringType(width);
      file_type = mem_type = string_type.get();
      space = Handle(H5Screate(H5S_SCALAR), H5Sclose);
    } else {
      const hsize_t dims[2] = {rows, cols};
      if (item.kind == kStrings) {
        string_type = stringType(width);
        file_type = mem_type = string_type.get();
      } else {
        file_type = fileTypeOf(item.kind);
        mem_type = memTypeOf(item.kind);
      }
      space = Handle(H5Screate_simple(cols > 1 ? 2 : 1, dims, nullptr), H5Sclose);
    }
    Handle dcpl = creationList();
    Handle d(check(H5Dcreate2(file_.get(), item.name.c_str(), file_type, space.get(), H5P_DEFAULT,
                              dcpl.get(), H5P_DEFAULT),
                   context("cannot create dataset " + item.name)),
             H5Dclose);
    reserve(d.get());
    // Rank 0 writes the data alone (an independent transfer); a failure is agreed below.
    const bool empty = item.kind != kText && rows == 0;
    if (rank_ == 0 && !empty &&
        H5Dwrite(d.get(), mem_type, H5S_ALL, H5S_ALL, independent_.get(), item.bytes.data()) < 0 &&
        !error) {
      error = context("cannot write dataset " + item.name + ": " + hdf5ErrorMessage() +
                      freeSpaceNote(directoryOf(path_)));
    }
    writeInfo(item.name, shapes[4 * i + 3], item.info);
    if (item.kind == kText) writeAttribute<std::uint64_t>(item.name, "length", rows);
  }
  agree(error, comm_);
}

// --- replicated datasets: reading -------------------------------------------------------------

void File::readWhole(hid_t id, const std::string& dataset, hid_t mem_type, void* out,
                     std::uint64_t elements, int element_bytes, std::vector<std::uint64_t> dims) {
  std::optional<std::string> error;
  if (elements > 0) {
    if (H5Dread(id, mem_type, H5S_ALL, H5S_ALL, independent_.get(), out) < 0) {
      error = context("cannot read dataset " + dataset + ": " + hdf5ErrorMessage());
    }
  }
  agree(error, comm_);
  const std::uint64_t partial = checksumPartial(out, elements, element_bytes, 0);
  verify(dataset, checksumFinish(partial, elements), std::move(dims));
}

template <typename T>
std::vector<T> File::readTable(const std::string& dataset, std::uint64_t rows, std::size_t cols) {
  Dataset d = open<T>(dataset, rows, cols);  // checks type and shape
  std::vector<T> out(rows * cols);
  readWhole(d.id_.get(), dataset, Type<T>::mem(), out.data(), rows * cols, sizeof(T), d.dims_);
  return out;
}

std::vector<std::string> File::readStrings(const std::string& dataset, std::uint64_t count) {
  Handle d = openDataset(dataset);
  Handle type(H5Dget_type(d.get()), H5Tclose);
  if (H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) > 0) {
    throw CheckpointError(context("dataset " + dataset + " holds " + describeType(type.get()) +
                                  " values, expected fixed-length strings"));
  }
  const std::size_t width = H5Tget_size(type.get());
  Handle space(H5Dget_space(d.get()), H5Sclose);
  const auto found = spaceDims(space.get());
  if (found != std::vector<std::uint64_t>{count}) {
    throw CheckpointError(context("dataset " + dataset + " has shape " + describeDims(found) +
                                  cat(", expected ", count, " (inconsistent sizes)")));
  }
  std::vector<char> bytes(std::max<std::uint64_t>(count * width, 1), '\0');
  Handle mem_type = stringType(width);
  readWhole(d.get(), dataset, mem_type.get(), bytes.data(), count * width, 1, found);
  std::vector<std::string> out(count);
  for (std::size_t i = 0; i < count; ++i) {
    const char* s = bytes.data() + i * width;
    out[i].assign(s, strnlen(s, width));
  }
  return out;
}

std::string File::readText(const std::string& dataset) {
  Handle d = openDataset(dataset);
  Handle type(H5Dget_type(d.get()), H5Tclose);
  Handle space(H5Dget_space(d.get()), H5Sclose);
  if (H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) > 0 ||
      H5Sget_simple_extent_type(space.get()) != H5S_SCALAR) {
    throw CheckpointError(context("dataset " + dataset + " is not a fixed-length string"));
  }
  std::vector<char> bytes(H5Tget_size(type.get()), '\0');
  Handle mem_type = stringType(bytes.size());
  readWhole(d.get(), dataset, mem_type.get(), bytes.data(), bytes.size(), 1, {});
  const auto length = readAttribute<std::uint64_t>(dataset, "length");
  if (length > bytes.size()) {
    throw CheckpointError(context(cat("dataset ", dataset, ": length ", length, " exceeds its ",
                                      bytes.size(), " stored bytes")));
  }
  return std::string(bytes.data(), length);
}

std::vector<std::uint64_t> File::dims(const std::string& dataset) const {
  Handle d = openDataset(dataset);
  Handle space(check(H5Dget_space(d.get()), context("dataset " + dataset)), H5Sclose);
  return spaceDims(space.get());
}

#define POLYDEM_H5_INSTANTIATE(T)                                                                 \
  template Dataset File::create<T>(const std::string&, std::uint64_t, std::size_t, const Info&);  \
  template Dataset File::open<T>(const std::string&, std::uint64_t, std::size_t);                 \
  template void ReplicatedBatch::table<T>(const std::string&, const std::vector<T>&, std::size_t, \
                                          const Info&);                                           \
  template std::vector<T> File::readTable<T>(const std::string&, std::uint64_t, std::size_t);
POLYDEM_H5_INSTANTIATE(double)
POLYDEM_H5_INSTANTIATE(std::uint64_t)
POLYDEM_H5_INSTANTIATE(std::int64_t)
POLYDEM_H5_INSTANTIATE(std::uint32_t)
POLYDEM_H5_INSTANTIATE(std::int32_t)
POLYDEM_H5_INSTANTIATE(std::uint8_t)
#undef POLYDEM_H5_INSTANTIATE

}  // namespace polydem::hdf5

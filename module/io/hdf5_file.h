// A thin collective layer over parallel HDF5 for checkpoints (internal to io/): RAII handles,
// HDF5 errors turned into CheckpointErrors that name the file and the dataset, agreement of all
// ranks on every error, and datasets written and read as per-rank hyperslabs with collective
// transfers and a rank-count independent checksum (io/checkpoint_checksum.h).
//
// Every File method is collective and ends with an agreement: if it failed on any rank, it throws
// the lowest failing rank's message on every rank, so that no rank is left waiting in a collective.
#pragma once

#include <hdf5.h>
#include <mpi.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "io/checkpoint.h"

namespace polydem::io::h5 {

/// Owns an HDF5 identifier and releases it with the matching H5?close function.
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle() = default;
  Handle(hid_t id, Closer closer) : id_(id), closer_(closer) {}
  Handle(Handle&& other) noexcept : id_(other.id_), closer_(other.closer_) { other.id_ = -1; }
  Handle& operator=(Handle&& other) noexcept;
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { reset(); }
  void reset();
  /// Gives up ownership without closing; returns the identifier.
  hid_t release() {
    const hid_t id = id_;
    id_ = -1;
    return id;
  }
  hid_t get() const { return id_; }

 private:
  hid_t id_ = -1;
  Closer closer_ = nullptr;
};

/// Turns HDF5's automatic error printing off while alive (errors become exceptions instead).
class ErrorSilencer {
 public:
  ErrorSilencer();
  ~ErrorSilencer();
  ErrorSilencer(const ErrorSilencer&) = delete;
  ErrorSilencer& operator=(const ErrorSilencer&) = delete;

 private:
  H5E_auto2_t function_ = nullptr;
  void* data_ = nullptr;
};

/// The outermost and innermost messages of HDF5's error stack (then cleared).
std::string hdf5ErrorMessage();

/// If any rank passes an error, every rank throws CheckpointError with the lowest failing rank's
/// message. Collective.
void agree(const std::optional<std::string>& error, MPI_Comm comm);

/// The rows of a dataset one rank moves: [offset, offset + rows) of `total`; `max_rows` is the
/// largest `rows` of any rank (it fixes the number of collective rounds).
struct Slice {
  std::uint64_t offset = 0, rows = 0, total = 0, max_rows = 0;
  bool replicated = false;  // every rank moves all rows (so checksums are not summed over ranks)
};
/// Writing: this rank contributes `rows` rows after those of lower ranks (collective).
Slice writerSlice(std::uint64_t rows, MPI_Comm comm);
/// Reading: rank r of P gets the r-th of P nearly equal contiguous slices (the first total % P
/// ranks one row more).
Slice readerSlice(std::uint64_t total, int rank, int ranks);
/// Every rank moves all rows (replicated data on read; on write, give rank 0 all rows and the
/// others none through writerSlice instead).
Slice wholeSlice(std::uint64_t total);

/// Attributes a dataset carries besides its checksum.
struct Info {
  std::string units;        // "m", "kg m^2/s"...; empty for counts, indices and flags
  std::string description;  // one line
};

class File {
 public:
  /// Creates (truncating) `path` for parallel writing with collective metadata.
  static File create(const std::filesystem::path& path, MPI_Comm comm,
                     const CheckpointIoOptions& options);
  /// Opens `path` read-only for parallel reading.
  static File open(const std::filesystem::path& path, MPI_Comm comm,
                   const CheckpointIoOptions& options);
  File(File&&) noexcept = default;
  ~File();

  /// Flushes (writable files: MPI_File_sync) and closes; errors are agreed and thrown.
  void close();

  MPI_Comm comm() const { return comm_; }
  const std::string& name() const { return name_; }
  /// "checkpoint FILE: " + what: the start of every message about this file.
  std::string context(const std::string& what) const;

  // --- writing ----------------------------------------------------------------------------------
  void createGroup(const std::string& group, const std::string& description);

  /// Dataset of slice.total rows of `cols` elements (cols == 1: a vector of slice.total, else a
  /// slice.total x cols matrix); this rank's rows from `local` (slice.rows * cols elements).
  template <typename T>
  void write(const std::string& dataset, std::span<const T> local, std::size_t cols,
             const Slice& slice, const Info& info);
  /// A vector of fixed-length strings (NUL padded to the longest), written from rank 0's values.
  void writeStrings(const std::string& dataset, const std::vector<std::string>& values,
                    const Info& info);
  /// A scalar fixed-length string holding `text` (rank 0's), with its byte length as "length".
  void writeText(const std::string& dataset, const std::string& text, const Info& info);

  template <typename T>
  void writeAttribute(const std::string& object, const std::string& attribute,
                      std::span<const T> values);
  template <typename T>
  void writeAttribute(const std::string& object, const std::string& attribute, T value) {
    writeAttribute(object, attribute, std::span<const T>(&value, 1));
  }
  void writeAttribute(const std::string& object, const std::string& attribute,
                      const std::string& text);

  // --- reading (every dataset's type, shape and checksum are verified) --------------------------
  /// Dimensions of `dataset`; throws naming it if it is missing.
  std::vector<std::uint64_t> dims(const std::string& dataset) const;
  /// Reads this rank's rows of a dataset that must have slice.total rows of `cols` elements.
  /// With `prefix` > 0 every rank also reads rows [0, prefix) (replicated rows ahead of the
  /// distributed ones); they come first in the result.
  template <typename T>
  std::vector<T> read(const std::string& dataset, std::size_t cols, const Slice& slice,
                      std::uint64_t prefix = 0);
  std::vector<std::string> readStrings(const std::string& dataset, std::uint64_t count);
  std::string readText(const std::string& dataset);

  template <typename T>
  std::vector<T> readAttribute(const std::string& object, const std::string& attribute,
                               std::size_t count);
  template <typename T>
  T readAttribute(const std::string& object, const std::string& attribute) {
    return readAttribute<T>(object, attribute, 1)[0];
  }
  std::string readStringAttribute(const std::string& object, const std::string& attribute);

  /// Datasets read so far, with their verified checksums.
  const std::vector<CheckpointDatasetInfo>& datasets() const { return datasets_; }

 private:
  File(std::string name, MPI_Comm comm, const CheckpointIoOptions& options, bool writable);
  bool exists(const std::string& path) const;
  Handle openDataset(const std::string& dataset) const;
  void finishWrite(const std::string& dataset, std::uint64_t partial, std::uint64_t elements,
                   const Info& info, std::optional<std::string> error);
  void verify(const std::string& dataset, std::uint64_t partial, std::uint64_t elements,
              bool sum_over_ranks, std::vector<std::uint64_t> dims,
              std::optional<std::string> error);
  void transfer(bool writing, hid_t dataset, hid_t mem_type, void* buffer, std::size_t row_bytes,
                std::size_t cols, const Slice& slice) const;
  void writeAttributeRaw(const std::string& object, const std::string& attribute, hid_t file_type,
                         hid_t mem_type, std::size_t count, const void* values);
  void readAttributeRaw(const std::string& object, const std::string& attribute, hid_t file_type,
                        hid_t mem_type, std::size_t count, void* values) const;

  std::string name_;
  MPI_Comm comm_ = MPI_COMM_NULL;
  int rank_ = 0;
  CheckpointIoOptions options_;
  bool writable_ = false;
  Handle file_;
  Handle transfer_;  // dataset transfer property list: collective MPI-IO
  std::vector<CheckpointDatasetInfo> datasets_;
};

}  // namespace polydem::io::h5

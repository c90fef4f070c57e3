// A thin collective layer over parallel HDF5 for checkpoints and snapshots: RAII handles,
// HDF5 errors turned into CheckpointErrors that name the file and the dataset, datasets moved as
// per-rank hyperslabs in collective rounds with a rank-count independent checksum
// (hdf5/checksum.h), and replicated tables written from rank 0 in one batch.
//
// Errors and agreement. Metadata operations (groups, datasets, attributes) are collective calls
// made with the same arguments on every rank, and with collective metadata reads every rank sees
// the same metadata, so they fail alike everywhere and throw at once. What can fail on some ranks
// only (data transfers, flushes, the caller's data) is remembered and agreed on at a few points
// (file creation, the end of each table, close): there, if any rank failed, every rank throws
// the lowest failing rank's message, so that no rank is left waiting in a collective.
//
// Full disks. A writable file takes its disk space before HDF5 writes into it (disk_space.h):
// when the file and each dataset are created, the blocks up to the end of the data allocated so
// far plus room for the metadata after it are allocated, rank 0 allocates and every rank learns
// the result, so a full disk throws the same CheckpointError ("no space left on device") on
// every rank, and the metadata flush of the close that follows writes only into blocks the file
// already holds.
#pragma once

#include <hdf5.h>
#include <mpi.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "polydem/hdf5/disk_space.h"
#include "polydem/hdf5/file_digest.h"
#include "polydem/hdf5/file_options.h"

namespace polydem::hdf5 {

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
};
/// Writing: this rank contributes `rows` rows after those of lower ranks (collective).
Slice writerSlice(std::uint64_t rows, MPI_Comm comm);
/// Reading: rank r of P gets the r-th of P nearly equal contiguous slices (the first total % P
/// ranks one row more).
Slice readerSlice(std::uint64_t total, int rank, int ranks);

/// Collective rounds of at most `per_round` rows each, enough for `slice.max_rows`; the rows of
/// this rank in round k are [begin(k), end(k)) of its slice (empty once it has none left).
struct Rounds {
  Rounds(const Slice& slice, std::size_t row_bytes, std::size_t round_bytes);
  std::uint64_t count = 0, per_round = 1, rows = 0;
  std::uint64_t begin(std::uint64_t k) const { return std::min(rows, k * per_round); }
  std::uint64_t end(std::uint64_t k) const { return std::min(rows, (k + 1) * per_round); }
};

/// Attributes a dataset carries besides its checksum.
struct Info {
  std::string units;        // "m", "kg m^2/s"...; empty for counts, indices and flags
  std::string description;  // one line
};

class File;

/// One distributed dataset being written or read in collective rounds; File::finish() completes
/// it.
class Dataset {
 public:
  Dataset(Dataset&&) noexcept = default;
  /// Collective (every rank calls it equally often, with rows = 0 when it has none): writes
  /// `rows` rows of `data` at file row `first_row`.
  void write(const void* data, std::uint64_t first_row, std::uint64_t rows);
  /// A run of rows: `rows` rows at file row `first`.
  struct Run {
    std::uint64_t first = 0, rows = 0;
  };
  /// Collective like write(), for rows scattered over the file: writes the runs (in increasing
  /// file order, not overlapping), their rows one after the other in `data`, and adds them to
  /// the checksum (no hash() call needed).
  void writeRuns(const void* data, std::span<const Run> runs);
  /// Collective likewise: reads `rows` rows at file row `first_row` into `data`.
  void read(void* data, std::uint64_t first_row, std::uint64_t rows);
  /// Adds `rows` rows of `data`, file rows [first_row, first_row + rows), to the checksum. Not
  /// collective; every row must be added by exactly one rank (for rows all ranks read: rank 0).
  void hash(const void* data, std::uint64_t first_row, std::uint64_t rows);

 private:
  friend class File;
  Dataset() = default;
  void transfer(bool writing, void* data, std::uint64_t first_row, std::uint64_t rows);

  std::string context_;  // "checkpoint FILE: "
  std::string name_;
  Handle id_, file_space_;
  hid_t transfer_list_ = -1;
  hid_t mem_type_ = -1;
  std::size_t element_bytes_ = 0, cols_ = 1;
  std::uint64_t total_ = 0;
  std::vector<std::uint64_t> dims_;
  Info info_;
  bool writing_ = false;
  std::uint64_t partial_ = 0;  // this rank's share of the checksum sum
  std::optional<std::string> error_;
};

/// Replicated datasets (tables, string lists, texts) collected on every rank and written from
/// rank 0's values by File::write(batch): one broadcast carries their shapes and checksums, rank 0
/// writes the data. The other ranks' values are ignored.
class ReplicatedBatch {
 public:
  explicit ReplicatedBatch(MPI_Comm comm);
  template <typename T>
  void table(const std::string& name, const std::vector<T>& values, std::size_t cols,
             const Info& info);
  /// A vector of fixed-length strings, NUL padded to the longest.
  void strings(const std::string& name, const std::vector<std::string>& values, const Info& info);
  /// A scalar fixed-length string with its byte length as attribute "length".
  void text(const std::string& name, const std::string& text, const Info& info);

 private:
  friend class File;
  struct Item {
    std::string name;
    Info info;
    int kind = 0;  // element type code (hdf5_types.h), kStrings or kText
    // Filled on rank 0, broadcast to the others:
    std::uint64_t rows = 0, cols = 1, width = 0, checksum = 0;
    std::vector<std::byte> bytes;  // rank 0 only
  };
  Item& add(const std::string& name, const Info& info, int kind);
  bool rank0_ = false;
  std::vector<Item> items_;
};

class File {
 public:
  /// Creates (truncating) `path` for parallel writing with collective metadata. Messages name
  /// `shown_as` (the final name of a file written under a temporary one), or else `path`.
  static File create(const std::filesystem::path& path, MPI_Comm comm,
                     const CheckpointIoOptions& options, const std::string& shown_as = "");
  /// Opens `path` read-only for parallel reading.
  static File open(const std::filesystem::path& path, MPI_Comm comm,
                   const CheckpointIoOptions& options);
  File(File&&) noexcept = default;
  ~File();

  /// Flushes (writable files: MPI_File_sync) and closes; errors are agreed and thrown: the
  /// flush's before HDF5's collective close is entered, the close's after it.
  void close();

  MPI_Comm comm() const { return comm_; }
  const CheckpointIoOptions& options() const { return options_; }
  /// "checkpoint FILE: " + what: the start of every message about this file.
  std::string context(const std::string& what) const;

  // --- distributed datasets: create or open, move rows in rounds, finish ------------------------
  /// A dataset of `total` rows of `cols` elements (cols == 1: a vector, else a matrix).
  template <typename T>
  Dataset create(const std::string& dataset, std::uint64_t total, std::size_t cols,
                 const Info& info);
  /// An existing dataset, which must hold T values in `total` rows of `cols` elements.
  template <typename T>
  Dataset open(const std::string& dataset, std::uint64_t total, std::size_t cols);
  /// Completes datasets (collective): agrees on their transfer errors, sums their checksums over
  /// the ranks (unless `replicated`: every rank hashed every row itself), and then stores the
  /// checksums and attributes (writing) or compares them with the stored ones (reading).
  void finish(std::span<Dataset* const> datasets, bool replicated = false);

  // --- replicated data --------------------------------------------------------------------------
  void createGroup(const std::string& group, const std::string& description);
  /// Writes a batch of replicated datasets (collective).
  void write(const ReplicatedBatch& batch);
  /// Every row of a table of `rows` rows, read by every rank; checksum verified.
  template <typename T>
  std::vector<T> readTable(const std::string& dataset, std::uint64_t rows, std::size_t cols = 1);
  std::vector<std::string> readStrings(const std::string& dataset, std::uint64_t count);
  std::string readText(const std::string& dataset);
  /// Dimensions of `dataset`; throws naming it if it is missing.
  std::vector<std::uint64_t> dims(const std::string& dataset) const;

  // --- attributes (collective metadata; values must be the same on every rank) -------------------
  template <typename T>
  void writeAttribute(const std::string& object, const std::string& attribute,
                      std::span<const T> values);
  template <typename T>
  void writeAttribute(const std::string& object, const std::string& attribute, T value) {
    writeAttribute(object, attribute, std::span<const T>(&value, 1));
  }
  void writeAttribute(const std::string& object, const std::string& attribute,
                      const std::string& text);
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
  /// The whole-file digest (hdf5/file_digest.h) of the file as it is now (collective).
  FileDigest digest() const;

 private:
  File(std::string name, MPI_Comm comm, const CheckpointIoOptions& options, bool writable);
  /// Writable files: takes the disk space up to the end of the data of `dataset` (just created)
  /// and of every dataset before it, plus room for the metadata that follows (disk_space.h).
  /// Collective: call it after every dataset is created, before its data is written. Throws
  /// CheckpointError on every rank if the disk is full.
  void reserve(hid_t dataset = -1);
  bool exists(const std::string& path) const;
  Handle openDataset(const std::string& dataset) const;
  /// The fields of a Dataset of T both create() and open() set, before the HDF5 handles.
  template <typename T>
  Dataset datasetOf(const std::string& dataset, std::uint64_t total, std::size_t cols) const;
  /// Reads a replicated dataset whole on every rank (independent transfer) and verifies it.
  void readWhole(hid_t id, const std::string& dataset, hid_t mem_type, void* out,
                 std::uint64_t elements, int element_bytes, std::vector<std::uint64_t> dims);
  void verify(const std::string& dataset, std::uint64_t computed, std::vector<std::uint64_t> dims);
  void writeInfo(const std::string& dataset, std::uint64_t checksum, const Info& info);
  void writeAttributeRaw(const std::string& object, const std::string& attribute, hid_t file_type,
                         hid_t mem_type, std::size_t count, const void* values);
  void readAttributeRaw(const std::string& object, const std::string& attribute, hid_t file_type,
                        hid_t mem_type, std::size_t count, void* values) const;

  std::string name_;  // in messages
  std::string path_;  // on disk
  MPI_Comm comm_ = MPI_COMM_NULL;
  int rank_ = 0;
  CheckpointIoOptions options_;
  bool writable_ = false;
  Handle file_;
  Handle collective_;   // dataset transfer list: collective MPI-IO
  Handle independent_;  // dataset transfer list: independent MPI-IO (replicated data)
  std::vector<CheckpointDatasetInfo> datasets_;
  DiskSpace space_;             // rank 0's descriptor (writable files)
  bool reserving_ = false;      // false: the file system cannot allocate ahead
  std::uint64_t data_end_ = 0;  // end of the data of the datasets created so far
  std::uint64_t reserved_ = 0;  // bytes allocated on disk (both the same on every rank)
};

}  // namespace polydem::hdf5

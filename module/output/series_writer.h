// series.csv: one row of numbers per output step (time, step, kinetic energy, force ratio, number
// of contacts, the state of monitored particles...), written by rank 0 with a header fixed at
// construction. Values are printed with %.17g, so reading a row back gives the same doubles bit
// for bit. Rows are buffered and flushed as whole lines (every `flush_rows` rows or
// `flush_seconds` of wall clock), so a plot made during the run never sees half a row.
//
// Column names are plain identifiers used by scripts: non-empty, unique, no comma, quote, space
// or line break. Convention understood by python_coupling/plots/plot_series.py: a column
// `<name>_analytic` is the analytical answer for `<name>`; units follow from the name (see there).
#pragma once

#include <mpi.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace polydem::output {

class SeriesWriter {
 public:
  struct Options {
    std::int64_t flush_rows = 1000;  // flush after this many buffered rows...
    double flush_seconds = 1.0;      // ...or when this much wall time has passed since the last
    /// Continuing a run from a checkpoint taken at this step: the existing file (same columns,
    /// which must include "step") keeps its rows up to and including this step and grows from
    /// there. Unset: a fresh file.
    std::optional<std::int64_t> resume_after_step;
  };

  /// Collective over `comm`: rank 0 validates the columns and creates (or trims) the file and
  /// writes the header. On failure every rank throws polydem::Error naming the path.
  SeriesWriter(std::string path, std::vector<std::string> columns, MPI_Comm comm);
  SeriesWriter(std::string path, std::vector<std::string> columns, MPI_Comm comm, Options options);
  /// Flushes what is buffered (errors are swallowed here; call close() to see them).
  ~SeriesWriter();
  SeriesWriter(const SeriesWriter&) = delete;
  SeriesWriter& operator=(const SeriesWriter&) = delete;

  /// Appends one row on rank 0 (other ranks ignore it; not collective). Throws polydem::Error if
  /// the row has the wrong length or the file cannot be written.
  void write(std::span<const double> row);
  void write(std::initializer_list<double> row) { write(std::span<const double>(row)); }
  /// Writes the buffered rows out now (rank 0).
  void flush();
  /// Flushes and closes; later writes throw.
  void close();

  const std::string& path() const { return path_; }
  const std::vector<std::string>& columns() const { return columns_; }
  /// Index of a column; throws polydem::Error if there is none of that name.
  std::size_t column(std::string_view name) const;
  /// Rows written by this object (rank 0; 0 elsewhere).
  std::int64_t rows() const { return rows_; }

 private:
  void open(std::optional<std::int64_t> resume_after_step);

  std::string path_;
  std::vector<std::string> columns_;
  Options options_;
  bool writer_ = false;  // rank 0
  std::FILE* file_ = nullptr;
  std::string buffer_;
  std::int64_t buffered_rows_ = 0, rows_ = 0;
  std::chrono::steady_clock::time_point last_flush_;
};

/// Throws polydem::Error unless every name is a valid, unique column name (see above).
void validateSeriesColumns(const std::vector<std::string>& columns);

}  // namespace polydem::output

#include "polydem/output/series_writer.h"

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/output/output_file.h"

namespace polydem::output {

namespace {

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (true) {
    const auto comma = line.find(',', start);
    out.push_back(line.substr(start, comma - start));
    if (comma == std::string::npos) return out;
    start = comma + 1;
  }
}

}  // namespace

void validateSeriesColumns(const std::vector<std::string>& columns) {
  if (columns.empty()) throw Error("series.csv: no columns");
  std::set<std::string> seen;
  for (const auto& name : columns) {
    if (name.empty() || name.find_first_of(",\"' \t\r\n") != std::string::npos) {
      throw Error(cat("series.csv: column name '", name,
                      "' must be non-empty without commas, quotes, spaces or line breaks (it "
                      "may come from a particle label)"));
    }
    if (!seen.insert(name).second) throw Error(cat("series.csv: column '", name, "' twice"));
  }
}

SeriesWriter::SeriesWriter(std::string path, std::vector<std::string> columns, MPI_Comm comm)
    : SeriesWriter(std::move(path), std::move(columns), comm, Options{}) {}

SeriesWriter::SeriesWriter(std::string path, std::vector<std::string> columns, MPI_Comm comm,
                           Options options)
    : path_(std::move(path)), columns_(std::move(columns)), options_(options) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  writer_ = rank == 0;
  std::string error;
  if (writer_) {
    try {
      validateSeriesColumns(columns_);
      open(options_.resume_after_step);
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  throwIfAnyRankFailed(error, comm);
  last_flush_ = std::chrono::steady_clock::now();
}

void SeriesWriter::open(std::optional<std::int64_t> resume_after_step) {
  const std::string header = join(columns_, ",") + "\n";
  std::string kept = header;
  if (resume_after_step) {
    std::ifstream in(path_);
    if (in) {
      std::string line;
      std::getline(in, line);
      if (line + "\n" != header) {
        throw Error(cat("cannot resume ", path_, ": its columns are '", line, "', this run's '",
                        join(columns_, ","), "'"));
      }
      const std::size_t step_column = column("step");
      int line_number = 1;
      while (std::getline(in, line)) {
        ++line_number;
        const auto cells = splitCsv(line);
        const char* text = cells.size() == columns_.size() ? cells[step_column].c_str() : "";
        char* end = nullptr;
        const double step = std::strtod(text, &end);
        if (*text == '\0' || *end != '\0') {
          // A torn last line (the run was killed mid-write) is dropped; anything else is not ours.
          if (in.peek() == std::char_traits<char>::eof()) break;
          throw Error(cat(path_, ":", line_number, ": cannot resume: not a row of this series"));
        }
        if (step <= static_cast<double>(*resume_after_step)) kept += line + "\n";
      }
    }
  }
  writeFileAtomic(path_, kept);
  file_ = std::fopen(path_.c_str(), "ab");
  if (!file_) throw Error(cat("cannot open ", path_, ": ", std::strerror(errno)));
}

SeriesWriter::~SeriesWriter() {
  if (file_) {
    if (!buffer_.empty()) std::fwrite(buffer_.data(), 1, buffer_.size(), file_);
    std::fclose(file_);
  }
}

std::size_t SeriesWriter::column(std::string_view name) const {
  for (std::size_t i = 0; i < columns_.size(); ++i) {
    if (columns_[i] == name) return i;
  }
  throw Error(cat(path_, ": no column '", name, "' (columns: ", join(columns_, ","), ")"));
}

void SeriesWriter::write(std::span<const double> row) {
  if (!writer_) return;
  if (row.size() != columns_.size()) {
    throw Error(cat(path_, ": a row of ", row.size(), " values for ", columns_.size(), " columns"));
  }
  if (!file_) throw Error(cat(path_, ": written after close()"));
  char cell[32];
  for (std::size_t i = 0; i < row.size(); ++i) {
    std::snprintf(cell, sizeof cell, i ? ",%.17g" : "%.17g", row[i]);
    buffer_ += cell;
  }
  buffer_ += '\n';
  ++rows_;
  ++buffered_rows_;
  const auto now = std::chrono::steady_clock::now();
  if (buffered_rows_ >= options_.flush_rows ||
      std::chrono::duration<double>(now - last_flush_).count() >= options_.flush_seconds) {
    flush();
  }
}

void SeriesWriter::flush() {
  if (!file_) return;
  errno = 0;
  if ((!buffer_.empty() &&
       std::fwrite(buffer_.data(), 1, buffer_.size(), file_) != buffer_.size()) ||
      std::fflush(file_) != 0) {
    throw Error(cat("cannot write ", path_, ": ", std::strerror(errno)));
  }
  buffer_.clear();
  buffered_rows_ = 0;
  last_flush_ = std::chrono::steady_clock::now();
}

void SeriesWriter::close() {
  if (!file_) return;
  flush();
  std::FILE* file = file_;
  file_ = nullptr;
  if (std::fclose(file) != 0) {
    throw Error(cat("cannot write ", path_, ": ", std::strerror(errno)));
  }
}

}  // namespace polydem::output

// Output files that are never seen half-written: everything polydem writes for a person or a
// script (snapshots, summary.json) goes to "<path>.tmp" first and is renamed into place only once
// it is complete, so an interrupted run or a full disk leaves the previous file or none, never a
// truncated one. Plus the one collective rule of parallel output: if any rank fails, all throw.
#pragma once

#include <mpi.h>

#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>

#include "polydem/core/error.h"

namespace polydem::output {

/// A file written under "<path>.tmp" and renamed to `path` by commit(). Destroyed without
/// commit() (an exception on the way), it removes the temporary and leaves `path` untouched.
/// Every failure (cannot create, disk full, rename refused) throws polydem::Error naming the path.
class AtomicFile {
 public:
  explicit AtomicFile(std::string path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  void write(const void* data, std::size_t bytes);
  void write(std::string_view text) { write(text.data(), text.size()); }
  /// Flushes, closes and renames into place. Nothing may be written afterwards.
  void commit();

  const std::string& path() const { return path_; }

 private:
  [[noreturn]] void fail(const std::string& what);

  std::string path_, tmp_path_;
  std::FILE* file_ = nullptr;
};

/// Writes `content` to `path` atomically (see AtomicFile).
void writeFileAtomic(const std::string& path, std::string_view content);

/// Collective over `comm`. `error` is this rank's failure message (empty: no failure). When any
/// rank failed, every rank throws OutputError with the message of the lowest failing rank, so
/// that no rank is left waiting in a later collective call while another one unwinds.
void throwIfAnyRankFailed(const std::string& error, MPI_Comm comm);

/// Creates `dir` and its parents if they do not exist; throws polydem::Error naming it otherwise.
void createDirectories(const std::string& dir);

}  // namespace polydem::output

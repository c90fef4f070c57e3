#include "polydem/output/output_file.h"

#include <cerrno>
#include <climits>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <vector>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"

namespace polydem::output {

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)), tmp_path_(path_ + ".tmp") {
  file_ = std::fopen(tmp_path_.c_str(), "wb");
  if (!file_) {
    throw Error(cat("cannot create ", tmp_path_, " (for ", path_, "): ", std::strerror(errno)));
  }
  // Large stdio buffer: snapshot pieces are written in many small base64 chunks.
  std::setvbuf(file_, nullptr, _IOFBF, std::size_t{1} << 20);
}

AtomicFile::~AtomicFile() {
  if (file_) {
    std::fclose(file_);
    std::remove(tmp_path_.c_str());
  }
}

void AtomicFile::fail(const std::string& what) {
  const int code = errno;
  if (file_) {
    std::fclose(file_);
    file_ = nullptr;
  }
  std::remove(tmp_path_.c_str());
  throw Error(
      cat("cannot write ", path_, ": ", what, code ? ": " : "", code ? std::strerror(code) : ""));
}

void AtomicFile::write(const void* data, std::size_t bytes) {
  if (!file_) throw Error(cat("cannot write ", path_, ": already committed"));
  errno = 0;
  if (bytes > 0 && std::fwrite(data, 1, bytes, file_) != bytes) fail("write failed");
}

void AtomicFile::commit() {
  if (!file_) throw Error(cat("cannot write ", path_, ": already committed"));
  errno = 0;
  // A full disk often shows only here, when the stdio buffer goes out.
  if (std::fflush(file_) != 0) fail("flush failed");
  std::FILE* file = file_;
  file_ = nullptr;
  if (std::fclose(file) != 0) {
    std::remove(tmp_path_.c_str());
    throw Error(cat("cannot write ", path_, ": close failed: ", std::strerror(errno)));
  }
  if (std::rename(tmp_path_.c_str(), path_.c_str()) != 0) {
    const int code = errno;
    std::remove(tmp_path_.c_str());
    throw Error(cat("cannot rename ", tmp_path_, " to ", path_, ": ", std::strerror(code)));
  }
}

void writeFileAtomic(const std::string& path, std::string_view content) {
  AtomicFile file(path);
  file.write(content);
  file.commit();
}

void throwIfAnyRankFailed(const std::string& error, MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  const int mine = error.empty() ? INT_MAX : rank;
  int first = INT_MAX;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm);
  if (first == INT_MAX) return;
  int length = static_cast<int>(error.size());
  MPI_Bcast(&length, 1, MPI_INT, first, comm);
  std::vector<char> message(error.begin(), error.end());
  message.resize(static_cast<std::size_t>(length));
  MPI_Bcast(message.data(), length, MPI_CHAR, first, comm);
  std::string text(message.begin(), message.end());
  if (rank != first) text = cat(text, " (on rank ", first, ")");
  throw OutputError(text);
}

void createDirectories(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw Error(cat("cannot create directory ", dir, ": ", ec.message()));
  if (!std::filesystem::is_directory(dir, ec)) {
    throw Error(cat("cannot create directory ", dir, ": a file of that name is in the way"));
  }
}

}  // namespace polydem::output

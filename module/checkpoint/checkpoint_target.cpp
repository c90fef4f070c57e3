// What writeCheckpoint may write over. The file is written under a temporary name and renamed
// onto the path, and a rename replaces whatever has the name: a FIFO, a device (/dev/null, when
// run as root) or somebody's unrelated file would be silently replaced by a checkpoint. So a
// checkpoint goes only to a new path, over an empty file, or over a polydem checkpoint; a
// symbolic link is followed (the file it names is replaced, the link stays) under the same rules.
#include <hdf5.h>

#include <string>
#include <vector>

#include "polydem/checkpoint/checkpoint.h"
#include "polydem/checkpoint/checkpoint_layout.h"
#include "polydem/core/file_kind.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/hdf5/hdf5_file.h"

namespace polydem::checkpoint {

namespace {

namespace fs = std::filesystem;

/// Whether `file` is an HDF5 file whose root attribute `format` is polydem's (any version).
bool isPolydemCheckpoint(const fs::path& file) {
  const hdf5::ErrorSilencer silence;
  const hdf5::Handle f(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (f.get() < 0 || H5Aexists(f.get(), "format") <= 0) return false;
  const hdf5::Handle a(H5Aopen(f.get(), "format", H5P_DEFAULT), H5Aclose);
  if (a.get() < 0) return false;
  const hdf5::Handle t(H5Aget_type(a.get()), H5Tclose);
  if (t.get() < 0 || H5Tget_class(t.get()) != H5T_STRING || H5Tis_variable_str(t.get()) != 0) {
    return false;
  }
  std::vector<char> text(H5Tget_size(t.get()) + 1, '\0');
  if (H5Aread(a.get(), t.get(), text.data()) < 0) return false;
  return std::string(text.data()) == layout::kFormatName;
}

/// Empty if a checkpoint may be written for `path`, else why not; `target` is the file to write.
std::string problemWith(const fs::path& path, fs::path& target) {
  std::error_code ec;
  target = path;
  const fs::file_status link = fs::symlink_status(path, ec);
  if (link.type() == fs::file_type::not_found) return "";  // a new file
  if (ec) return "cannot be inspected: " + ec.message();
  std::string via;
  if (fs::is_symlink(link)) {
    const fs::path named = fs::read_symlink(path, ec);
    target = fs::canonical(path, ec);
    if (ec) return cat("is a symbolic link to ", named.string(), ", which does not exist");
    via = cat("is a symbolic link to ", target.string(), ", which ");
  }
  if (const std::string kind = notARegularFile(target.string()); !kind.empty()) {
    return cat(via, kind, "; a checkpoint is written only to a new path or over a checkpoint");
  }
  const std::uintmax_t bytes = fs::file_size(target, ec);
  if (ec) return "cannot be inspected: " + ec.message();
  if (bytes == 0 || isPolydemCheckpoint(target)) return "";
  return cat(via.empty() ? std::string("exists and ") : via, "is not a polydem checkpoint (", bytes,
             " bytes); polydem writes a checkpoint only to a new path or over a checkpoint: ",
             "remove the file or choose another path");
}

}  // namespace

fs::path checkpointTarget(const fs::path& path, MPI_Comm comm) {
  std::optional<std::string> problem;
  fs::path target = path;
  if (mpi::rank(comm) == 0) {
    if (const std::string p = problemWith(path, target); !p.empty()) {
      problem = "checkpoint " + path.string() + ": " + p;
    }
  }
  hdf5::agree(problem, comm);
  std::string text = target.string();
  std::uint64_t length = text.size();
  MPI_Bcast(&length, 1, MPI_UINT64_T, 0, comm);
  text.resize(length);
  MPI_Bcast(text.data(), static_cast<int>(length), MPI_CHAR, 0, comm);
  return text;
}

}  // namespace polydem::checkpoint

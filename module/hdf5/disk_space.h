// Disk space taken for a file before parallel HDF5 writes into it (used by hdf5_file.cpp).
//
// Parallel HDF5 cannot end a file cleanly once a write fails on some ranks only: a full disk
// makes one rank's part of a collective metadata flush fail, that rank leaves the flush early,
// and the ranks then wait for each other in different collective calls of HDF5's close (forever,
// at 100 % CPU), or the library crashes later on. So the file layer (hdf5_file.h) allocates the
// blocks on disk before HDF5 may write into them: rank 0 calls fallocate(2) for everything HDF5
// has allocated in the file so far plus some room ahead, every rank learns the result, and a
// full disk ends the write with the same clean error on every rank, before any of those bytes
// are written. HDF5 then only writes into blocks the file already holds, and its close, which
// cuts the file back to the size HDF5 allocated, has nothing left to fail on.
#pragma once

#include <cstdint>
#include <string>

namespace polydem::hdf5 {

/// Rank 0's descriptor of the file being written, and the bytes allocated so far.
class DiskSpace {
 public:
  DiskSpace() = default;
  DiskSpace(DiskSpace&& other) noexcept;
  DiskSpace& operator=(DiskSpace&& other) noexcept;
  DiskSpace(const DiskSpace&) = delete;
  DiskSpace& operator=(const DiskSpace&) = delete;
  ~DiskSpace() { close(); }

  /// Opens `path`, which exists; 0 or the errno.
  int open(const std::string& path);
  /// Allocates bytes [0, `bytes`) of the file on disk (and makes the file at least that long);
  /// 0 or the errno: ENOSPC, EDQUOT, EFBIG..., or EOPNOTSUPP where the file system cannot
  /// allocate ahead. A failed call gives back the blocks it took.
  int allocate(std::uint64_t bytes);
  /// Cuts the file to nothing, giving back all its blocks: for a file that is being abandoned,
  /// so that HDF5's close, which still writes its metadata, finds room on a full disk.
  void discard();
  void close();

 private:
  int fd_ = -1;
  std::uint64_t allocated_ = 0;
};

/// Whether an errno of DiskSpace::allocate() says the file system cannot allocate ahead (the
/// file is then written without taking its space first), rather than that the space is not there.
bool cannotAllocateAhead(int code);

/// What a failed allocation of `bytes` bytes for a file in `dir` means, for a message: "no space
/// left on device: 1234 bytes free in DIR, the file needs about 5678" (ENOSPC), "disk quota
/// exceeded..." (EDQUOT), "file too large..." (EFBIG), otherwise the errno's text.
std::string allocationFailure(int code, std::uint64_t bytes, const std::string& dir);

/// "; N bytes free in DIR", or "; no space left on device: N bytes free in DIR" when fewer than
/// a few blocks are free: appended to a failed write's message, whose cause MPI-IO does not tell.
std::string freeSpaceNote(const std::string& dir);

/// The directory of `path` ("." for a bare file name).
std::string directoryOf(const std::string& path);

}  // namespace polydem::hdf5

#include "polydem/hdf5/disk_space.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "polydem/core/strings.h"

namespace polydem::hdf5 {

DiskSpace::DiskSpace(DiskSpace&& other) noexcept : fd_(other.fd_), allocated_(other.allocated_) {
  other.fd_ = -1;
}

DiskSpace& DiskSpace::operator=(DiskSpace&& other) noexcept {
  if (this != &other) {
    close();
    fd_ = other.fd_;
    allocated_ = other.allocated_;
    other.fd_ = -1;
  }
  return *this;
}

int DiskSpace::open(const std::string& path) {
  close();
  fd_ = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  allocated_ = 0;
  return fd_ < 0 ? errno : 0;
}

int DiskSpace::allocate(std::uint64_t bytes) {
  if (fd_ < 0) return EBADF;
  if (bytes <= allocated_) return 0;
  struct stat before {};
  if (::fstat(fd_, &before) != 0) return errno;
  int result = 0;
  do {
    result = ::fallocate(fd_, 0, static_cast<off_t>(allocated_),
                         static_cast<off_t>(bytes - allocated_)) == 0
                 ? 0
                 : errno;
  } while (result == EINTR);
  if (result == 0) {
    allocated_ = bytes;
  } else {
    // Some file systems keep the blocks of a failed call; cutting the file back to its length
    // gives them back (HDF5 has written nothing beyond it). Nothing more to do if that fails.
    [[maybe_unused]] const int undone = ::ftruncate(fd_, before.st_size);
  }
  return result;
}

void DiskSpace::discard() {
  if (fd_ < 0) return;
  [[maybe_unused]] const int ignored = ::ftruncate(fd_, 0);  // best effort: the file is removed
  allocated_ = 0;
}

void DiskSpace::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

bool cannotAllocateAhead(int code) {
  return code == EOPNOTSUPP || code == ENOSYS || code == EINVAL || code == ENODEV || code == ESPIPE;
}

namespace {

/// Bytes an unprivileged writer may still use in `dir`, or -1 if statvfs fails.
long long freeBytes(const std::string& dir) {
  struct statvfs info {};
  if (::statvfs(dir.c_str(), &info) != 0) return -1;
  return static_cast<long long>(info.f_bavail) * static_cast<long long>(info.f_frsize);
}

std::string lowercaseFirst(std::string text) {
  if (!text.empty() && text[0] >= 'A' && text[0] <= 'Z') text[0] = static_cast<char>(text[0] + 32);
  return text;
}

}  // namespace

std::string allocationFailure(int code, std::uint64_t bytes, const std::string& dir) {
  const long long free = freeBytes(dir);
  const std::string where =
      free >= 0 ? cat(free, " bytes free in ", dir, ", the file needs about ", bytes)
                : cat("the file needs about ", bytes, " bytes in ", dir);
  return cat(lowercaseFirst(std::strerror(code)), ": ", where);
}

std::string freeSpaceNote(const std::string& dir) {
  const long long free = freeBytes(dir);
  if (free < 0) return "";
  // A file system with fewer than a few blocks left is the likeliest cause of a failed write.
  constexpr long long kNearlyFull = 64 * 1024;
  return cat(free < kNearlyFull ? "; no space left on device: " : "; ", free, " bytes free in ",
             dir);
}

std::string directoryOf(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

}  // namespace polydem::hdf5

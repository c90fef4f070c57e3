// Checkpoint file names in a run directory, keeping the newest K of them, and removing the
// temporary files of writes that were cut short.
#include <signal.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <string_view>

#include "polydem/checkpoint/checkpoint.h"
#include "polydem/core/error.h"
#include "polydem/core/strings.h"

namespace polydem::io {

namespace {

namespace fs = std::filesystem;

constexpr std::string_view kPrefix = "checkpoint_";
constexpr std::string_view kSuffix = ".h5";
constexpr int kStepDigits = 12;

/// The step of a name made by checkpointFileName, or -1 for any other name.
std::int64_t stepOf(const std::string& name) {
  if (name.size() != kPrefix.size() + kStepDigits + kSuffix.size()) return -1;
  if (name.compare(0, kPrefix.size(), kPrefix) != 0) return -1;
  if (name.compare(name.size() - kSuffix.size(), kSuffix.size(), kSuffix) != 0) return -1;
  std::int64_t step = 0;
  for (std::size_t i = kPrefix.size(); i < kPrefix.size() + kStepDigits; ++i) {
    if (name[i] < '0' || name[i] > '9') return -1;
    step = 10 * step + (name[i] - '0');
  }
  return step;
}

/// The writer's pid of a temporary file's name (checkpoint name + ".tmp." + digits), or -1.
long temporaryPid(const std::string& name) {
  constexpr std::string_view kTmp = ".tmp.";
  const std::size_t base = kPrefix.size() + kStepDigits + kSuffix.size();
  if (name.size() <= base + kTmp.size() || stepOf(name.substr(0, base)) < 0) return -1;
  if (name.compare(base, kTmp.size(), kTmp) != 0) return -1;
  const std::string digits = name.substr(base + kTmp.size());
  if (digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) return -1;
  return std::stol(digits);
}

/// Whether a process with this id exists on this machine (kill with signal 0 sends nothing).
bool processExists(long pid) {
  if (pid <= 0) return false;
  return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;
}

}  // namespace

fs::path checkpointFileName(const fs::path& dir, std::int64_t step) {
  if (step < 0) throw Error(cat("checkpointFileName: step ", step, " is negative"));
  char digits[32];
  std::snprintf(digits, sizeof digits, "%0*lld", kStepDigits, static_cast<long long>(step));
  return dir / (std::string(kPrefix) + digits + std::string(kSuffix));
}

std::vector<CheckpointFile> listCheckpoints(const fs::path& dir) {
  std::vector<CheckpointFile> out;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    if (!entry.is_regular_file(ec)) continue;
    const std::int64_t step = stepOf(entry.path().filename().string());
    if (step >= 0) out.push_back({step, entry.path()});
  }
  std::sort(out.begin(), out.end(),
            [](const CheckpointFile& a, const CheckpointFile& b) { return a.step < b.step; });
  return out;
}

std::vector<fs::path> pruneCheckpoints(const fs::path& dir, int keep) {
  if (keep < 1) throw Error(cat("pruneCheckpoints: keep = ", keep, " must be at least 1"));
  const auto files = listCheckpoints(dir);
  std::vector<fs::path> deleted;
  const std::size_t n = files.size() > static_cast<std::size_t>(keep)
                            ? files.size() - static_cast<std::size_t>(keep)
                            : 0;
  for (std::size_t i = 0; i < n; ++i) {
    std::error_code ec;
    if (fs::remove(files[i].path, ec)) deleted.push_back(files[i].path);
  }
  return deleted;
}

std::vector<TemporaryCheckpointFile> listTemporaryCheckpoints(const fs::path& dir) {
  std::vector<TemporaryCheckpointFile> out;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    if (!entry.is_regular_file(ec)) continue;
    const long pid = temporaryPid(entry.path().filename().string());
    if (pid < 0) continue;
    TemporaryCheckpointFile t;
    t.path = entry.path();
    t.pid = pid;
    t.bytes = entry.file_size(ec);
    t.writer_alive = processExists(pid);
    out.push_back(std::move(t));
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.path < b.path; });
  return out;
}

std::vector<TemporaryCheckpointFile> removeStaleTemporaryCheckpoints(const fs::path& dir) {
  auto files = listTemporaryCheckpoints(dir);
  for (auto& t : files) {
    std::error_code ec;
    if (!t.writer_alive) t.removed = fs::remove(t.path, ec);
  }
  return files;
}

}  // namespace polydem::io

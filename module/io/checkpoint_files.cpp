// Checkpoint file names in a run directory, and keeping the newest K of them.
#include <algorithm>
#include <cstdio>
#include <string_view>

#include "core/error.h"
#include "core/strings.h"
#include "io/checkpoint.h"

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

}  // namespace polydem::io

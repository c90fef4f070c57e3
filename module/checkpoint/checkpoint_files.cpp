// Checkpoint file names in a run directory, each with the id of the run that wrote it; keeping the
// newest K of one run's (never another run's), and removing the temporary files of writes that
// were cut short.
#include <signal.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <optional>
#include <random>
#include <set>
#include <string_view>

#include "polydem/checkpoint/checkpoint.h"
#include "polydem/core/error.h"
#include "polydem/core/strings.h"

namespace polydem::checkpoint {

namespace {

namespace fs = std::filesystem;

constexpr std::string_view kPrefix = "checkpoint_";
constexpr std::string_view kSuffix = ".h5";
constexpr int kStepDigits = 12;

bool isRunId(std::string_view id) {
  return id.size() == static_cast<std::size_t>(kCheckpointRunIdDigits) &&
         id.find_first_not_of("0123456789abcdef") == std::string_view::npos;
}

/// A name made by checkpointFileName (checkpoint_<step>_<run id>.h5), or one of a file written
/// before run ids (checkpoint_<step>.h5, run id ""); nothing for any other name.
std::optional<CheckpointFile> parseName(const std::string& name) {
  const std::size_t plain = kPrefix.size() + kStepDigits + kSuffix.size();
  const std::size_t with_id = plain + 1 + kCheckpointRunIdDigits;
  if (name.size() != plain && name.size() != with_id) return std::nullopt;
  if (name.compare(0, kPrefix.size(), kPrefix) != 0) return std::nullopt;
  if (name.compare(name.size() - kSuffix.size(), kSuffix.size(), kSuffix) != 0) return std::nullopt;
  CheckpointFile f;
  for (std::size_t i = kPrefix.size(); i < kPrefix.size() + kStepDigits; ++i) {
    if (name[i] < '0' || name[i] > '9') return std::nullopt;
    f.step = 10 * f.step + (name[i] - '0');
  }
  if (name.size() == with_id) {
    const std::size_t at = kPrefix.size() + kStepDigits;
    f.run_id = name.substr(at + 1, kCheckpointRunIdDigits);
    if (name[at] != '_' || !isRunId(f.run_id)) return std::nullopt;
  }
  return f;
}

/// The writer's pid of a temporary file's name (checkpoint name + ".tmp." + digits), or -1.
long temporaryPid(const std::string& name) {
  constexpr std::string_view kTmp = ".tmp.";
  const std::size_t at = name.rfind(kTmp);
  if (at == std::string::npos || !parseName(name.substr(0, at))) return -1;
  const std::string digits = name.substr(at + kTmp.size());
  if (digits.empty() || digits.size() > 9 ||
      digits.find_first_not_of("0123456789") != std::string::npos) {
    return -1;
  }
  return std::stol(digits);
}

/// Whether a process with this id exists on this machine (kill with signal 0 sends nothing).
bool processExists(long pid) {
  if (pid <= 0) return false;
  return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;
}

}  // namespace

fs::path checkpointFileName(const fs::path& dir, std::int64_t step, const std::string& run_id) {
  if (step < 0) throw Error(cat("checkpointFileName: step ", step, " is negative"));
  if (!isRunId(run_id)) {
    throw Error(cat("checkpointFileName: run id '", run_id, "' is not ", kCheckpointRunIdDigits,
                    " lowercase hexadecimal digits"));
  }
  char digits[32];
  std::snprintf(digits, sizeof digits, "%0*lld", kStepDigits, static_cast<long long>(step));
  return dir / cat(kPrefix, digits, "_", run_id, kSuffix);
}

std::vector<CheckpointFile> listCheckpoints(const fs::path& dir) {
  std::vector<CheckpointFile> out;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    // Not following symbolic links: a link is not a file polydem wrote.
    if (!entry.is_regular_file(ec) || entry.is_symlink(ec)) continue;
    if (auto f = parseName(entry.path().filename().string())) {
      f->path = entry.path();
      out.push_back(std::move(*f));
    }
  }
  std::sort(out.begin(), out.end(), [](const CheckpointFile& a, const CheckpointFile& b) {
    return a.step != b.step ? a.step < b.step : a.run_id < b.run_id;
  });
  return out;
}

std::vector<fs::path> pruneCheckpoints(const fs::path& dir, const std::string& run_id, int keep) {
  if (keep < 1) throw Error(cat("pruneCheckpoints: keep = ", keep, " must be at least 1"));
  if (!isRunId(run_id)) throw Error(cat("pruneCheckpoints: '", run_id, "' is not a run id"));
  std::vector<fs::path> mine;  // by step
  for (const auto& f : listCheckpoints(dir)) {
    if (f.run_id == run_id) mine.push_back(f.path);
  }
  std::vector<fs::path> deleted;
  const std::size_t n = mine.size() > static_cast<std::size_t>(keep)
                            ? mine.size() - static_cast<std::size_t>(keep)
                            : 0;
  for (std::size_t i = 0; i < n; ++i) {
    std::error_code ec;
    if (fs::remove(mine[i], ec)) deleted.push_back(mine[i]);
  }
  return deleted;
}

std::string newCheckpointRunId(const fs::path& dir) {
  std::random_device entropy;
  std::set<std::string> used;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    const std::size_t tmp = name.rfind(".tmp.");
    if (auto f = parseName(tmp == std::string::npos ? name : name.substr(0, tmp))) {
      used.insert(f->run_id);
    }
  }
  for (;;) {
    char id[16];
    std::snprintf(id, sizeof id, "%08x", static_cast<unsigned>(entropy()));
    if (!used.contains(id)) return id;
  }
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

}  // namespace polydem::checkpoint

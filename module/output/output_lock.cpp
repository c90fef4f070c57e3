#include "polydem/output/output_lock.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <fstream>
#include <sstream>

#include "polydem/core/error.h"
#include "polydem/core/file_kind.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"

namespace polydem::output {

namespace {

namespace fs = std::filesystem;

constexpr const char* kHeader = "polydem output lock";

std::string hostName() {
  char name[256] = {};
  if (::gethostname(name, sizeof name - 1) != 0) return "unknown";
  return name;
}

/// The start time of process `pid` in clock ticks since boot (field 22 of /proc/<pid>/stat), or
/// -1 where it cannot be read. A process id can be reused; the pair (pid, start) cannot.
long long processStartTicks(long pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t name_end = stat.rfind(')');  // the command name may hold spaces and ')'
  if (name_end == std::string::npos) return -1;
  std::istringstream fields(stat.substr(name_end + 1));
  std::string field;
  for (int i = 3; i <= 22; ++i) {  // fields after the name start at 3
    if (!(fields >> field)) return -1;
  }
  try {
    return std::stoll(field);
  } catch (const std::exception&) {
    return -1;
  }
}

std::string utcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

std::string describe(const LockHolder& h) {
  return cat("process ", h.pid, " on host ", h.host,
             h.started.empty() ? std::string() : ", started " + h.started);
}

bool sameHolder(const LockHolder& a, const LockHolder& b) {
  return a.pid == b.pid && a.host == b.host && a.start_ticks == b.start_ticks;
}

/// Why the holder (on this host) is gone, or "" if it may still run.
std::string goneBecause(const LockHolder& h) {
  if (::kill(static_cast<pid_t>(h.pid), 0) != 0 && errno == ESRCH) return "which is gone";
  const long long start = processStartTicks(h.pid);
  if (h.start_ticks >= 0 && start >= 0 && start != h.start_ticks) {
    return "whose process id now belongs to another process";
  }
  return "";
}

/// Creates the lock file with O_EXCL (fails if any file has the name) and writes the holder.
/// Returns errno of the creation (0: created), or -1 if it was created but could not be written.
int createLockFile(const fs::path& file, const LockHolder& me) {
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) return errno;
  const std::string text = cat(kHeader, "\npid ", me.pid, "\nhost ", me.host, "\nstart_ticks ",
                               me.start_ticks, "\nstarted ", me.started, "\n");
  const bool written = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  const bool synced = ::fsync(fd) == 0;
  if (::close(fd) != 0 || !written || !synced) {
    ::unlink(file.c_str());
    return -1;
  }
  return 0;
}

std::string busyMessage(const fs::path& dir, const fs::path& file, const LockHolder& h,
                        const LockHolder& me) {
  const std::string head =
      cat("output folder ", dir.string(), " is in use: ", file.string(), " names ", describe(h));
  if (h.host != me.host) {
    return cat(head, ", which cannot be checked from host ", me.host,
               "; if that run has ended (killed or crashed), remove ", file.string(),
               "; or choose another output folder");
  }
  if (h.pid == me.pid) return cat(head, " (this process, which is writing into it already)");
  return cat(head, ", which is still running; wait for that run to end or choose another ",
             "output folder (if process ", h.pid, " is not a polydem run, remove ", file.string(),
             ")");
}

}  // namespace

LockHolder thisProcess() {
  LockHolder me;
  me.pid = static_cast<long>(::getpid());
  me.host = hostName();
  me.start_ticks = processStartTicks(me.pid);
  me.started = utcNow();
  return me;
}

bool readLockHolder(const fs::path& file, LockHolder& holder) {
  std::ifstream in(file);
  std::string line;
  if (!std::getline(in, line) || line != kHeader) return false;
  LockHolder h;
  bool has_pid = false, has_host = false;
  while (std::getline(in, line)) {
    const std::size_t space = line.find(' ');
    if (space == std::string::npos) continue;
    const std::string key = line.substr(0, space), value = line.substr(space + 1);
    try {
      if (key == "pid") {
        h.pid = std::stol(value);
        has_pid = h.pid > 0;
      } else if (key == "host") {
        h.host = value;
        has_host = !value.empty();
      } else if (key == "start_ticks") {
        h.start_ticks = std::stoll(value);
      } else if (key == "started") {
        h.started = value;
      }
    } catch (const std::exception&) {
      return false;
    }
  }
  if (!has_pid || !has_host) return false;
  holder = h;
  return true;
}

LockAttempt tryLockOutput(const fs::path& dir) {
  const fs::path file = dir / kOutputLockName;
  const LockHolder me = thisProcess();
  std::string takeover;
  // A few attempts: between finding a stale lock and removing it, another run may take it.
  for (int attempt = 0; attempt < 3; ++attempt) {
    const int created = createLockFile(file, me);
    if (created == 0) return {true, takeover};
    if (created != EEXIST) {
      return {false, cat("cannot create the lock file ", file.string(), ": ",
                         created < 0 ? std::string("cannot write it") : std::strerror(created))};
    }
    // Not read unless it is a regular file: a FIFO would block the reader.
    if (const std::string kind = notARegularFile(file.string()); !kind.empty()) {
      return {false, cat("output folder ", dir.string(), " cannot be locked: ", file.string(), " ",
                         kind, " (polydem's lock file has this name); remove it")};
    }
    LockHolder holder;
    if (!readLockHolder(file, holder)) {
      return {false, cat("output folder ", dir.string(), " is in use or was left locked: ",
                         file.string(), " names no holder (being written, empty or damaged); ",
                         "if no polydem run writes into ", dir.string(), ", remove it")};
    }
    const std::string gone = holder.host == me.host ? goneBecause(holder) : std::string();
    if (gone.empty()) return {false, busyMessage(dir, file, holder, me)};
    LockHolder again;  // the file may have been replaced since it was read
    if (!readLockHolder(file, again) || !sameHolder(again, holder)) continue;
    if (::unlink(file.c_str()) != 0 && errno != ENOENT) {
      return {false, cat("cannot remove the stale lock file ", file.string(), " of ",
                         describe(holder), ": ", std::strerror(errno))};
    }
    takeover = cat("took over ", file.string(), " from ", describe(holder), ", ", gone,
                   " (a run that was killed or crashed)");
  }
  return {false, cat("output folder ", dir.string(), ": ", file.string(),
                     " changed while it was being taken (other runs are starting into it)")};
}

void unlockOutput(const fs::path& dir) {
  const fs::path file = dir / kOutputLockName;
  LockHolder holder;
  if (readLockHolder(file, holder) && sameHolder(holder, thisProcess())) ::unlink(file.c_str());
}

OutputLock::OutputLock(const fs::path& dir, MPI_Comm comm) : dir_(dir) {
  std::string refused;
  if (mpi::rank(comm) == 0) {
    std::error_code ec;
    created_dir_ = fs::create_directories(dir_, ec);
    if (ec) {
      refused = cat("cannot create the output folder ", dir_.string(), ": ", ec.message());
    } else {
      const LockAttempt attempt = tryLockOutput(dir_);
      held_ = attempt.held;
      if (!held_) refused = attempt.message;
      if (held_ && !attempt.message.empty()) log::warning(attempt.message);
    }
  }
  std::uint64_t length = refused.size();
  MPI_Bcast(&length, 1, MPI_UINT64_T, 0, comm);
  refused.resize(length);
  MPI_Bcast(refused.data(), static_cast<int>(length), MPI_CHAR, 0, comm);
  if (refused.empty()) return;
  if (created_dir_) {
    std::error_code ec;
    fs::remove(dir_, ec);  // only if empty
  }
  throw OutputError(refused);
}

OutputLock::~OutputLock() {
  if (held_) unlockOutput(dir_);
  if (created_dir_) {
    std::error_code ec;
    if (fs::is_empty(dir_, ec) && !ec) fs::remove(dir_, ec);
  }
}

}  // namespace polydem::output

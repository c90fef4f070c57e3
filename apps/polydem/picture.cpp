#include "picture.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <vector>

#include "polydem/core/logging.h"
#include "polydem/core/strings.h"

extern char** environ;

namespace polydem::app {

namespace {

namespace fs = std::filesystem;

/// The interpreter: $POLYDEM_PYTHON, else Debian's /usr/bin/python3 (which has the numpy, h5py
/// and matplotlib of scripts/install-deps; a python3 earlier on PATH may not).
std::string python() {
  if (const char* p = std::getenv("POLYDEM_PYTHON"); p && *p) return p;
  return "/usr/bin/python3";
}

/// The script: $POLYDEM_PLOTS_DIR/render_frames.py, else the source tree this polydem was built
/// from, else the tree around the executable (build/bin/polydem -> ../../python_coupling).
std::string script() {
  const char* name = "render_frames.py";
  std::vector<fs::path> candidates;
  if (const char* d = std::getenv("POLYDEM_PLOTS_DIR"); d && *d) candidates.emplace_back(d);
#ifdef POLYDEM_SOURCE_DIR
  candidates.emplace_back(fs::path(POLYDEM_SOURCE_DIR) / "python_coupling" / "plots");
#endif
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) candidates.push_back(exe.parent_path() / ".." / ".." / "python_coupling" / "plots");
  for (const auto& dir : candidates) {
    if (fs::is_regular_file(dir / name, ec)) return (dir / name).lexically_normal().string();
  }
  return "";
}

}  // namespace

std::string renderPicture(const std::string& out_dir) {
  const std::string py = python(), path = script();
  if (path.empty()) {
    log::warning(
        "no picture: render_frames.py not found (set POLYDEM_PLOTS_DIR to "
        "python_coupling/plots)");
    return "";
  }
  if (access(py.c_str(), X_OK) != 0) {
    log::warning(cat("no picture: ", py, " not found (set POLYDEM_PYTHON)"));
    return "";
  }
  std::vector<std::string> args = {py, path, out_dir};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  // posix_spawn, not system(): no shell to interpret the paths, and no fork of the MPI process's
  // address space.
  if (posix_spawn(&pid, py.c_str(), nullptr, nullptr, argv.data(), environ) != 0) {
    log::warning(cat("no picture: cannot start ", py));
    return "";
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    log::warning(cat("no picture: ", py, " ", path, " ", out_dir, " failed (exit status ",
                     WIFEXITED(status) ? WEXITSTATUS(status) : -1, ")"));
    return "";
  }
  const std::string png = out_dir + "/frames.png";
  log::info("wrote " + png);
  return png;
}

}  // namespace polydem::app

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

/// The script `name`: $POLYDEM_PLOTS_DIR/name, else the source tree this polydem was built from,
/// else the tree around the executable (build/bin/polydem -> ../../python_coupling).
std::string script(const char* name) {
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

/// Runs plots script `name` on `out_dir` with Python and waits for it; returns `png` when the
/// script succeeded, else "" after a warning that says why.
std::string runPlotScript(const char* name, const std::string& out_dir, const std::string& png,
                          const std::vector<std::string>& options = {}) {
  const std::string py = python(), path = script(name);
  const std::string what = fs::path(png).filename().string();
  if (path.empty()) {
    log::warning(
        cat("no ", png, ": ", name, " not found (set POLYDEM_PLOTS_DIR to python_coupling/plots)"));
    return "";
  }
  if (access(py.c_str(), X_OK) != 0) {
    log::warning(cat("no ", what, ": ", py, " not found (set POLYDEM_PYTHON)"));
    return "";
  }
  std::vector<std::string> args = {py, path, out_dir, "--out", png};
  args.insert(args.end(), options.begin(), options.end());
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  // posix_spawn, not system(): no shell to interpret the paths, and no fork of the MPI process's
  // address space.
  if (posix_spawn(&pid, py.c_str(), nullptr, nullptr, argv.data(), environ) != 0) {
    log::warning(cat("no ", png, ": cannot start ", py));
    return "";
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    log::warning(cat("no ", what, ": ", py, " ", path, " ", out_dir, " failed (exit status ",
                     WIFEXITED(status) ? WEXITSTATUS(status) : -1, ")"));
    return "";
  }
  log::info("wrote " + png);
  return png;
}

}  // namespace

const std::vector<std::string>& pictureFields() {
  static const std::vector<std::string> fields = {"speed", "displacement", "pressure", "joint"};
  return fields;
}

std::string renderPicture(const std::string& out_dir, const PictureOptions& options) {
  std::vector<std::string> args = {"--field", options.field};
  if (options.azimuth) args.insert(args.end(), {"--azimuth", shortest(*options.azimuth)});
  return runPlotScript("render_frames.py", out_dir, out_dir + "/frames.png", args);
}

std::string plotSeries(const std::string& out_dir) {
  return runPlotScript("plot_series.py", out_dir, out_dir + "/series.png");
}

std::string plotThickness(const std::string& out_dir) {
  return runPlotScript("plot_thickness.py", out_dir, out_dir + "/thickness.png");
}

std::string plotRealizations(const std::string& out_dir) {
  return runPlotScript("plot_realizations.py", out_dir, out_dir + "/realizations.png");
}

}  // namespace polydem::app

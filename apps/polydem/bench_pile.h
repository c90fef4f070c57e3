// The settled pile that `polydem bench yade` and `polydem bench lammps` run in polydem and in the
// peer code: randomly turned unit cubes settled in a box by polydem's equilibrium stage, then the
// same number of steps from that state in each code, with the same time step, density,
// stiffness, friction and damping (bench_yade.cpp, bench_lammps.cpp say how each peer's
// parameters are matched).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "commands.h"
#include "polydem/setup/setup.h"

namespace polydem::app {

struct PileBenchOptions {
  std::int64_t particles = 1000;
  std::int64_t layers = 10;
  std::int64_t settle = 150000;  // most equilibrium steps (1,000 cubes: about settled)
  std::int64_t steps = 100;      // timed steps
  std::int64_t warmup = 10;
  std::vector<std::string> kernels = {"gjk-epa-ipm", "distance-potential"};
  std::vector<std::string> models;  // contact models (penalty kernels); default: all
  std::string peer;                 // the peer's executable; empty: found on the PATH
  std::string keep;                 // directory for the peer's input and output
  std::uint64_t seed = 1;
};

inline constexpr double kPileDensity = 2650.0;  // kg/m^3
inline constexpr double kPileKn = 1e8;          // N/m
inline constexpr double kPileKs = 5e7;          // N/m
inline constexpr double kPileFriction = 30.0;   // degrees
inline constexpr double kPileDamping = 0.1;     // local (non-viscous) damping
inline constexpr double kPileDt = 1e-4;         // s
inline constexpr double kPileFaceArea = 1.0;    // m^2, a unit cube's face
inline constexpr double kPileInradius = 0.5;    // m, a unit cube's

/// The options both benches share (--particles, --layers, --settle, --steps, --warmup,
/// --kernels, --contact-models, --keep, --seed), and the peer's executable from `--<peer_flag>`.
PileBenchOptions parsePileOptions(Args& args, const std::string& peer_flag);

/// The box's inner width (the walls' inner faces are x, y = 0 and width; the floor is z = 0).
double pileBoxWidth(const PileBenchOptions& o);

/// The settled pile: the scene with the free cubes where polydem's equilibrium stage left them,
/// at rest; `steps_taken` and `reached` say how the stage ended.
setup::Setup settledPile(const PileBenchOptions& o, std::int64_t& steps_taken, bool& reached);

/// One code's timed run.
struct PileResult {
  std::string code, kernel, model;
  double particle_steps_per_second = 0.0;
  std::int64_t contacts = 0, particles = 0, steps = 0;
  double seconds = 0.0;
  long long peak_kb = 0;  // peak resident memory of the process that ran it (0: not measured)
  // The code's own count of what it holds, bytes: polydem's Simulation::memoryUse after the timed
  // steps (capacities times element sizes); LAMMPS's "Per MPI rank memory allocation" (max), an
  // estimate that can overflow (negative or terabytes on large piles); 0 where a code gives none.
  double counted_bytes = 0.0;
  std::vector<std::pair<std::string, double>> structures;  // polydem's count by structure, bytes
};

/// polydem's run of the settled pile with `kernel` and `model`: o.steps steps timed (CPU time of
/// this thread) after o.warmup.
PileResult runPolydemPile(setup::Setup scene, const std::string& kernel, const std::string& model,
                          const PileBenchOptions& o);

/// `override` if given and present, else `name` on the PATH; empty if neither.
std::string findExecutable(const std::string& name, const std::string& override_path);

/// A new temporary directory of our own (mkdtemp), or `keep` (created) when given.
std::string benchDirectory(const std::string& keep, const std::string& prefix);

/// Peak resident memory of this process (VmHWM, kB); 0 where /proc is not there.
long long selfPeakKb();

/// A peer's run: `command` under /bin/sh; its exit status and the peak resident memory of that
/// process and the processes it waited for (wait4), so that each peer's peak is its own.
struct ChildRun {
  int status = -1;
  long long peak_kb = 0;
};
ChildRun runChild(const std::string& command);

/// The last `count` lines of the text file at `path`, each on a new line and indented.
std::string fileTail(const std::filesystem::path& path, std::size_t count);

/// The peers' runs of the settled pile (bench_yade.cpp, bench_lammps.cpp): their input written
/// into `dir`, the peer at `exe` run there; no value (and a warning with the end of its output)
/// when it gives no timed run.
std::optional<PileResult> runYade(const setup::Setup& scene, const PileBenchOptions& o,
                                  const std::string& exe, const std::filesystem::path& dir);
std::optional<PileResult> runLammps(const setup::Setup& scene, const PileBenchOptions& o,
                                    const std::string& exe, const std::filesystem::path& dir);

}  // namespace polydem::app

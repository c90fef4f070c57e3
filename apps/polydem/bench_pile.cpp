// The settled pile of `polydem bench yade` and `polydem bench lammps` (bench_pile.h).
#include "bench_pile.h"

#include <stdlib.h>  // mkdtemp
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "generators/pile_scene.h"
#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/geometry/shapes.h"
#include "polydem/sim/memory_use.h"
#include "polydem/sim/simulation.h"

namespace polydem::app {

namespace {

// The lattice pitch: the cubes' bounding spheres apart.
const double kPitch = 2.0 * 0.5 * std::sqrt(3.0) * 1.05;

std::int64_t side(const PileBenchOptions& o) {
  return static_cast<std::int64_t>(
      std::ceil(std::sqrt(static_cast<double>(o.particles) / static_cast<double>(o.layers))));
}

// Turned unit cubes on a lattice whose pitch keeps their bounding spheres apart, above a floor
// between four walls (the P-PILE box).
setup::Setup boxScene(const PileBenchOptions& o) {
  setup::Setup s;
  s.file = "<generated peer comparison>";
  s.id = "P-PEER";
  s.title = "randomly turned unit cubes settled in a box";
  s.dt = kPileDt;
  s.gravity = Vec3(0, 0, -9.81);
  particles::Material rock;
  rock.name = "rock";
  rock.density = kPileDensity;
  rock.kn = kPileKn;
  rock.ks = kPileKs;
  rock.friction_angle = kPileFriction;
  rock.local_damping = kPileDamping;
  rock.penalty = kPileKn * kPileInradius / (2.0 * kPileFaceArea);
  s.materials.push_back(rock);
  s.shapes.push_back({"cube", geometry::shapes::box(Vec3::Constant(-0.5), Vec3::Constant(0.5)), 0});

  const std::int64_t n = side(o);
  Uid uid = sim::addPileBox(s, pileBoxWidth(o), static_cast<double>(o.layers) * kPitch + 2.0,
                            sim::kPileBoxThickness, true, 1);
  std::mt19937_64 rng(o.seed);
  std::normal_distribution<double> gauss;
  for (std::int64_t i = 0; i < o.particles; ++i) {
    const std::int64_t ix = i % n, iy = (i / n) % n, iz = i / (n * n);
    setup::ParticleSpec p;
    p.uid = uid++;
    p.shape = 0;
    p.material = 0;
    p.position = kPitch * Vec3(static_cast<double>(ix) + 0.5, static_cast<double>(iy) + 0.5,
                               static_cast<double>(iz) + 0.5);
    p.orientation = Quat(gauss(rng), gauss(rng), gauss(rng), gauss(rng)).normalized();
    s.particles.push_back(p);
  }
  s.output.series_every = 1000000;
  return s;
}

double pileThreadSeconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace

PileBenchOptions parsePileOptions(Args& args, const std::string& peer_flag) {
  PileBenchOptions o;
  o.models = setup::kContactModels;
  o.particles = args.integer("particles", o.particles, 1);
  o.layers = args.integer("layers", o.layers, 1);
  o.settle = args.integer("settle", o.settle, 1, Args::kInt64Max);
  o.steps = args.integer("steps", o.steps, 1, Args::kInt64Max);
  o.warmup = args.integer("warmup", o.warmup, 0, Args::kInt64Max);
  if (const auto k = args.value("kernels")) o.kernels = split(*k, ',');
  if (const auto m = args.value("contact-models")) o.models = split(*m, ',');
  for (const auto& m : o.models) {
    if (const auto e = setup::unknownContactModel(m); !e.empty()) {
      throw UsageError("--contact-models: " + e);
    }
  }
  o.peer = args.value(peer_flag, "");
  o.keep = args.value("keep", "");
  o.seed = static_cast<std::uint64_t>(args.integer("seed", 1, 0, Args::kInt64Max));
  if (o.kernels.empty() || o.models.empty()) {
    throw UsageError("--kernels and --contact-models need at least one name each");
  }
  return o;
}

double pileBoxWidth(const PileBenchOptions& o) {
  return static_cast<double>(side(o)) * kPitch;
}

setup::Setup settledPile(const PileBenchOptions& o, std::int64_t& steps_taken, bool& reached) {
  setup::Setup scene = boxScene(o);
  scene.equilibrium.enabled = true;
  scene.equilibrium.force_ratio = 1e-3;
  scene.equilibrium.max_steps = o.settle;
  sim::Simulation sim(scene, MPI_COMM_SELF);
  steps_taken = sim.runEquilibrium();
  reached = sim.equilibriumReached();
  // The free cubes only: the storage holds centroids, and the walls, vertex-list shapes whose
  // scene position is 0, would move by their centroid if theirs were copied.
  const auto& storage = sim.particles();
  for (std::size_t i = 0; i < storage.localCount(); ++i) {
    const auto& p = storage[i];
    if (!p.isFree()) continue;
    for (auto& spec : scene.particles) {
      if (spec.uid != p.uid) continue;
      spec.position = p.position;
      spec.orientation = p.orientation;
    }
  }
  scene.equilibrium.enabled = false;
  return scene;
}

PileResult runPolydemPile(setup::Setup scene, const std::string& kernel, const std::string& model,
                          const PileBenchOptions& o) {
  scene.kernel = kernel;
  scene.contact_model = model;
  sim::Simulation sim(scene, MPI_COMM_SELF);
  for (std::int64_t i = 0; i < o.warmup; ++i) sim.step();
  const double t0 = pileThreadSeconds();
  for (std::int64_t i = 0; i < o.steps; ++i) sim.step();
  const double seconds = pileThreadSeconds() - t0;
  const auto mon = sim.monitors();
  PileResult r{"polydem", kernel, model};
  r.particles = mon.particles;
  r.contacts = mon.contacts;
  r.steps = o.steps;
  r.seconds = seconds;
  r.particle_steps_per_second = static_cast<double>(mon.particles * o.steps) / seconds;
  r.peak_kb = selfPeakKb();
  const sim::MemoryUse use = sim.memoryUse();
  r.counted_bytes = static_cast<double>(sim::totalBytes(use));
  for (const auto& item : use)
    r.structures.emplace_back(item.name, static_cast<double>(item.bytes));
  return r;
}

std::string findExecutable(const std::string& name, const std::string& override_path) {
  if (!override_path.empty()) {
    return std::filesystem::exists(override_path) ? override_path : std::string();
  }
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    const auto candidate = std::filesystem::path(dir) / name;
    if (!dir.empty() && std::filesystem::exists(candidate)) return candidate.string();
  }
  return {};
}

std::string benchDirectory(const std::string& keep, const std::string& prefix) {
  if (!keep.empty()) {
    std::filesystem::create_directories(keep);
    return keep;
  }
  std::string name = (std::filesystem::temp_directory_path() / (prefix + "-XXXXXX")).string();
  if (mkdtemp(name.data()) == nullptr) throw Error("cannot create " + name);
  return name;
}

long long selfPeakKb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) == 0) return std::stoll(line.substr(6));
  }
  return 0;
}

ChildRun runChild(const std::string& command) {
  ChildRun run;
  std::fflush(nullptr);  // nothing buffered is written twice
  const pid_t pid = fork();
  if (pid < 0) throw Error("cannot start a process for: " + command);
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  rusage usage{};
  if (wait4(pid, &status, 0, &usage) != pid) return run;
  run.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  run.peak_kb = usage.ru_maxrss;  // the child's, or the largest of those it waited for
  return run;
}

std::string fileTail(const std::filesystem::path& path, std::size_t count) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  std::string line;
  while (std::getline(in, line)) lines.push_back(line);
  std::string tail;
  for (std::size_t i = lines.size() > count ? lines.size() - count : 0; i < lines.size(); ++i) {
    tail += "\n  " + lines[i];
  }
  return tail;
}

}  // namespace polydem::app

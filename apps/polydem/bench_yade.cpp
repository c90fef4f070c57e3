// polydem bench yade: polydem beside Yade (its Polyhedra, one core) on one scene: randomly turned
// unit cubes settled in a box. polydem settles the pile (the 3DEC-style equilibrium stage), then
// both codes start from that state, with no contact history, the same time step, density,
// stiffness, friction and local damping, and run the same number of steps; the run prints both
// codes' particle-steps per second (CPU time of one core) and their contact counts. Yade is
// optional: without it only polydem's figures are printed.
//
// Stiffness: polydem's penalty kernels push with kn * depth (N/m); Yade's Polyhedra law pushes
// with kn_Y * (overlap volume) (N/m^3, Law2_PolyhedraGeom_PolyhedraPhys_Volumetric), and takes
// kn_Y = young / 2 for two bodies of one material. A face-to-face contact of unit cubes (area
// A = 1 m^2) has the same stiffness in both with young = 2 kn / A; the distance potential's
// penalty gives it with penalty = kn r / (2 A) (docs/kernels/distance-potential.md: kn_eff =
// penalty A (1/r_A + 1/r_B), r = 0.5 m).
#include <stdlib.h>  // mkdtemp

#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "commands.h"
#include "generators/pile_scene.h"
#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/geometry/shapes.h"
#include "polydem/setup/setup.h"
#include "polydem/sim/simulation.h"

namespace polydem::app {

namespace {

struct Options {
  std::int64_t particles = 1000;
  std::int64_t layers = 10;
  std::int64_t settle = 150000;  // most equilibrium steps (1,000 cubes: about settled)
  std::int64_t steps = 100;      // timed steps
  std::int64_t warmup = 10;
  std::vector<std::string> kernels = {"gjk-epa-ipm", "distance-potential"};
  std::vector<std::string> models = io::kContactModels;  // contact models (penalty kernels)
  std::string yade;                                      // executable; empty: "yade" on the PATH
  std::string keep;  // directory for the Yade script and its output
  std::uint64_t seed = 1;
};

constexpr double kDensity = 2650.0;  // kg/m^3
constexpr double kKn = 1e8;          // N/m
constexpr double kKs = 5e7;          // N/m
constexpr double kFriction = 30.0;   // degrees
constexpr double kDamping = 0.1;     // local (non-viscous) damping, both codes
constexpr double kDt = 1e-4;         // s
constexpr double kFaceArea = 1.0;    // m^2, a unit cube's face
constexpr double kInradius = 0.5;    // m, a unit cube's

// Turned unit cubes on a lattice whose pitch keeps their bounding spheres apart, above a floor
// between four walls (the P-PILE box).
io::Scene boxScene(const Options& o) {
  io::Scene s;
  s.file = "<generated Yade comparison>";
  s.id = "P-YADE";
  s.title = "randomly turned unit cubes settled in a box";
  s.dt = kDt;
  s.gravity = Vec3(0, 0, -9.81);
  particles::Material rock;
  rock.name = "rock";
  rock.density = kDensity;
  rock.kn = kKn;
  rock.ks = kKs;
  rock.friction_angle = kFriction;
  rock.local_damping = kDamping;
  rock.penalty = kKn * kInradius / (2.0 * kFaceArea);
  s.materials.push_back(rock);
  s.shapes.push_back({"cube", geometry::shapes::box(Vec3::Constant(-0.5), Vec3::Constant(0.5)), 0});

  const double pitch = 2.0 * 0.5 * std::sqrt(3.0) * 1.05;
  const auto side = static_cast<std::int64_t>(
      std::ceil(std::sqrt(static_cast<double>(o.particles) / static_cast<double>(o.layers))));
  const double width = static_cast<double>(side) * pitch;
  Uid uid = sim::addPileBox(s, width, static_cast<double>(o.layers) * pitch + 2.0,
                            sim::kPileBoxThickness, true, 1);
  std::mt19937_64 rng(o.seed);
  std::normal_distribution<double> gauss;
  for (std::int64_t i = 0; i < o.particles; ++i) {
    const std::int64_t ix = i % side, iy = (i / side) % side, iz = i / (side * side);
    io::ParticleSpec p;
    p.uid = uid++;
    p.shape = 0;
    p.material = 0;
    p.position = pitch * Vec3(static_cast<double>(ix) + 0.5, static_cast<double>(iy) + 0.5,
                              static_cast<double>(iz) + 0.5);
    p.orientation = Quat(gauss(rng), gauss(rng), gauss(rng), gauss(rng)).normalized();
    s.particles.push_back(p);
  }
  s.output.series_every = 1000000;
  return s;
}

double threadSeconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// The settled pile: the scene with the particles where the equilibrium stage left them, at rest.
io::Scene settle(const Options& o, std::int64_t& steps_taken, bool& reached) {
  io::Scene scene = boxScene(o);
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

struct Result {
  std::string code, kernel, model;
  double particle_steps_per_second = 0.0;
  std::int64_t contacts = 0, particles = 0, steps = 0;
  double seconds = 0.0;
};

Result runPolydem(io::Scene scene, const std::string& kernel, const std::string& model,
                  const Options& o) {
  scene.kernel = kernel;
  scene.contact_model = model;
  sim::Simulation sim(scene, MPI_COMM_SELF);
  for (std::int64_t i = 0; i < o.warmup; ++i) sim.step();
  const double t0 = threadSeconds();
  for (std::int64_t i = 0; i < o.steps; ++i) sim.step();
  const double seconds = threadSeconds() - t0;
  const auto mon = sim.monitors();
  Result r{"polydem", kernel, model};
  r.particles = mon.particles;
  r.contacts = mon.contacts;
  r.steps = o.steps;
  r.seconds = seconds;
  r.particle_steps_per_second = static_cast<double>(mon.particles * o.steps) / seconds;
  return r;
}

// The Yade script: the same bodies (world vertices: Yade finds each body's centroid and axes),
// the same material and step, the Polyhedra engines; times o.steps steps after o.warmup.
std::string yadeScript(const io::Scene& scene, const Options& o) {
  std::ostringstream py;
  py.precision(17);
  py << "# generated by polydem bench yade\n"
     << "import math, time\nfrom yade import polyhedra_utils\n"
     << "mat = PolyhedraMat(density=" << kDensity << ", young=" << 2.0 * kKn / kFaceArea
     << ", poisson=" << kKs / kKn << ", frictionAngle=math.radians(" << kFriction << "))\n"
     << "O.materials.append(mat)\n"
     << "def body(v, fixed):\n"
     << "    b = polyhedra_utils.polyhedra(mat, v=[Vector3(*x) for x in v], fixed=fixed)\n"
     << "    b.dynamic = not fixed\n"  // a wall: neither integrated nor counted as a particle
     << "    return O.bodies.append(b)\n";
  for (const auto& p : scene.particles) {
    const auto& shape = scene.shapes[p.shape];
    const Mat3 r = p.orientation.toRotationMatrix();
    py << "body([";
    for (const Vec3& v : shape.vertices) {
      const Vec3 x = p.position + r * v;
      py << "(" << x.x() << "," << x.y() << "," << x.z() << "),";
    }
    py << "], " << (p.fixed ? "True" : "False") << ")\n";
  }
  py << "O.engines = [ForceResetter(),\n"
     << "    InsertionSortCollider([Bo1_Polyhedra_Aabb()]),\n"
     << "    InteractionLoop([Ig2_Polyhedra_Polyhedra_PolyhedraGeom()],\n"
     << "                    [Ip2_PolyhedraMat_PolyhedraMat_PolyhedraPhys()],\n"
     << "                    [Law2_PolyhedraGeom_PolyhedraPhys_Volumetric()]),\n"
     << "    NewtonIntegrator(damping=" << kDamping << ", gravity=(0, 0, -9.81))]\n"
     << "O.dt = " << scene.dt << "\n"
     << "O.run(" << o.warmup << ", True)\n"
     << "t0 = time.process_time()\n"
     << "O.run(" << o.steps << ", True)\n"
     << "seconds = time.process_time() - t0\n"
     // Contacts: interactions that push (the collider's other pairs are only near each other).
     << "contacts = sum(1 for i in O.interactions if i.isReal and i.phys.normalForce.norm() > 0)\n"
     << "free = sum(1 for b in O.bodies if b.dynamic)\n"
     << "print('POLYDEM-YADE %d %d %d %.9g' % (free, contacts, " << o.steps << ", seconds))\n";
  return py.str();
}

std::string yadeExecutable(const Options& o) {
  if (!o.yade.empty()) return std::filesystem::exists(o.yade) ? o.yade : std::string();
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    const auto candidate = std::filesystem::path(dir) / "yade";
    if (!dir.empty() && std::filesystem::exists(candidate)) return candidate.string();
  }
  return {};
}

std::optional<Result> runYade(const io::Scene& scene, const Options& o, const std::string& exe,
                              const std::filesystem::path& dir) {
  const auto script = dir / "yade_comparison.py";
  const auto log = dir / "yade_output.txt";
  std::ofstream(script) << yadeScript(scene, o);
  // One thread (-j1), no GUI (-n), exit when the script ends (-x).
  const std::string command =
      cat("'", exe, "' -n -j1 -x '", script.string(), "' > '", log.string(), "' 2>&1");
  const int rc = std::system(command.c_str());
  std::ifstream in(log);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("POLYDEM-YADE ", 0) != 0) continue;
    std::istringstream fields(line.substr(13));
    Result r{"yade", "Polyhedra", "volumetric"};
    fields >> r.particles >> r.contacts >> r.steps >> r.seconds;
    if (!fields || r.seconds <= 0.0) break;
    r.particle_steps_per_second = static_cast<double>(r.particles * r.steps) / r.seconds;
    return r;
  }
  // No result: show the end of Yade's output, which goes with a temporary directory.
  std::ifstream again(log);
  std::vector<std::string> lines;
  while (std::getline(again, line)) lines.push_back(line);
  std::string tail;
  for (std::size_t i = lines.size() > 20 ? lines.size() - 20 : 0; i < lines.size(); ++i) {
    tail += "\n  " + lines[i];
  }
  log::warning(cat("bench yade: no result from Yade (", exe, ", exit status ", rc,
                   "); the end of its output:", tail));
  return std::nullopt;
}

Options parseOptions(Args& args) {
  Options o;
  o.particles = args.integer("particles", o.particles, 1);
  o.layers = args.integer("layers", o.layers, 1);
  o.settle = args.integer("settle", o.settle, 1, Args::kInt64Max);
  o.steps = args.integer("steps", o.steps, 1, Args::kInt64Max);
  o.warmup = args.integer("warmup", o.warmup, 0, Args::kInt64Max);
  if (const auto k = args.value("kernels")) o.kernels = split(*k, ',');
  if (const auto m = args.value("contact-models")) o.models = split(*m, ',');
  for (const auto& m : o.models) {
    if (const auto e = io::unknownContactModel(m); !e.empty()) {
      throw UsageError("--contact-models: " + e);
    }
  }
  o.yade = args.value("yade", "");
  o.keep = args.value("keep", "");
  o.seed = static_cast<std::uint64_t>(args.integer("seed", 1, 0, Args::kInt64Max));
  if (o.kernels.empty() || o.models.empty()) {
    throw UsageError("--kernels and --contact-models need at least one name each");
  }
  return o;
}

}  // namespace

int benchYade(int argc, char** argv) {
  Args args(argc, argv, {"help"});
  if (args.flag("help")) {
    std::printf(
        "usage: polydem bench yade [--particles N] [--layers L] [--settle S] [--steps M]\n"
        "                          [--warmup W] [--kernels a,b] [--contact-models m,n]\n"
        "                          [--yade PATH] [--keep DIR] [--json FILE]\n"
        "  N randomly turned unit cubes (default 1000, L = 10 lattice layers) settled in a box by\n"
        "  polydem's equilibrium stage (at most S steps, default 150000), then M steps (default\n"
        "  100, after W = 10 untimed) from that state in polydem (each kernel, default\n"
        "  gjk-epa-ipm,distance-potential; each contact model, default sub-contacts,point:\n"
        "  the potential kernels' contacts keep one point in both) and in Yade's Polyhedra\n"
        "  when Yade is installed\n"
        "  (apt-get install yade; --yade: its executable): particle-steps per second of one core\n"
        "  (CPU time) and contact counts. Same time step, density, stiffness, friction and local\n"
        "  damping (see apps/polydem/bench_yade.cpp). --keep: where the Yade script and its\n"
        "  output go (default: a temporary directory, removed). Without Yade: polydem only.\n");
    return 0;
  }
  const Options o = parseOptions(args);
  const auto json_path = args.value("json");
  args.rejectUnknown();
  if (mpi::rank() != 0) return 0;  // one core: rank 0 measures
  log::setLevel(log::Level::kWarning);

  std::int64_t settle_steps = 0;
  bool reached = false;
  const io::Scene scene = settle(o, settle_steps, reached);
  std::printf(
      "P-YADE: %lld randomly turned unit cubes in a box, settled by polydem in %lld steps (force "
      "ratio %s 1e-3); then %lld steps (after %lld untimed) from rest in each code, dt %g s\n"
      "density %g kg/m^3, kn %g N/m (Yade young %g: same face-face stiffness), ks %g N/m, "
      "friction %g deg, local damping %g\n\n",
      static_cast<long long>(o.particles), static_cast<long long>(settle_steps),
      reached ? "reached" : "NOT reached", static_cast<long long>(o.steps),
      static_cast<long long>(o.warmup), kDt, kDensity, kKn, 2.0 * kKn / kFaceArea, kKs, kFriction,
      kDamping);

  std::vector<Result> results;
  for (const auto& kernel : o.kernels) {
    for (const auto& model : o.models) results.push_back(runPolydem(scene, kernel, model, o));
  }
  const std::string exe = yadeExecutable(o);
  if (exe.empty()) {
    std::printf("Yade not found (apt-get install yade, or --yade PATH): polydem only.\n\n");
  } else {
    const bool temporary = o.keep.empty();
    std::filesystem::path dir(o.keep);
    if (temporary) {  // a new directory of our own (mkdtemp), so that removing it is safe
      std::string name =
          (std::filesystem::temp_directory_path() / "polydem-bench-yade-XXXXXX").string();
      if (mkdtemp(name.data()) == nullptr) throw Error("bench yade: cannot create " + name);
      dir = name;
    } else {
      std::filesystem::create_directories(dir);
    }
    if (auto r = runYade(scene, o, exe, dir)) results.push_back(*r);
    if (temporary) std::filesystem::remove_all(dir);
  }
  const Result* yade = nullptr;
  for (const auto& r : results) {
    if (r.code == "yade") yade = &r;
  }
  std::printf("%-8s %-22s %-13s %10s %14s %8s %9s %12s\n", "code", "kernel", "model", "particles",
              "particle-st/s", "x Yade", "contacts", "per particle");
  for (const auto& r : results) {
    char ratio[32] = "-";
    if (yade != nullptr) {
      std::snprintf(ratio, sizeof ratio, "%.1f",
                    r.particle_steps_per_second / yade->particle_steps_per_second);
    }
    std::printf("%-8s %-22s %-13s %10lld %14.0f %8s %9lld %12.2f\n", r.code.c_str(),
                r.kernel.c_str(), r.model.c_str(), static_cast<long long>(r.particles),
                r.particle_steps_per_second, ratio, static_cast<long long>(r.contacts),
                static_cast<double>(r.contacts) / static_cast<double>(r.particles));
  }
  if (json_path) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& r : results) {
      out.push_back({{"code", r.code},
                     {"kernel", r.kernel},
                     {"contact_model", r.model},
                     {"particles", r.particles},
                     {"steps", r.steps},
                     {"seconds", r.seconds},
                     {"particle_steps_per_second", r.particle_steps_per_second},
                     {"contacts", r.contacts}});
    }
    std::ofstream(*json_path) << out.dump(2) << "\n";
    std::printf("written: %s\n", json_path->c_str());
  }
  return 0;
}

}  // namespace polydem::app

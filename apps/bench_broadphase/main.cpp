// bench_broadphase: P-BROADPHASE (Zhao section 5.5, table 7, figs. 43-44). Cubes of 1.0 m and
// 0.1 m edge settled in a layer on the ground; for each N the contact detection is run 10 times
// with the multi-level grid and with the single-level NBS grid, and the time per detection, per
// particle, the growth of the time per particle with N and the ratio NBS / multilevel are printed.
//
//   bench_broadphase [--n 1000,2000,...] [--layout pockets|sprinkle] [--big-fraction 0.1]
//                    [--repeats 10] [--rounds 5] [--margin 0] [--shuffle | --sort-cells]
//                    [--ground] [--lanes 2|4]
//                    [--methods multilevel,nbs] [--nbs-max-n N] [--json FILE]
#include <time.h>  // clock_gettime (POSIX)

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "cube_layer.h"
#include "polydem/broadphase/broad_phase.h"
#include "polydem/broadphase/multilevel_grid.h"
#include "polydem/broadphase/sphere_tests.h"
#include "polydem/core/error.h"
#include "polydem/core/strings.h"

namespace {

using polydem::Error;
using polydem::broadphase::BroadPhase;
using polydem::broadphase::CandidatePair;
using polydem::broadphase::SphereSet;

struct Options {
  std::vector<int> sizes = {1000, 2000, 3000, 4000, 5000, 6000, 10000, 30000, 100000};
  polydem::bench::CubeLayerSpec scene;
  int repeats = 10;  // detections per round, as in Zhao's figs. 43-44
  int rounds = 5;    // rounds of `repeats` detections; the fastest detection is kept
  double margin = 0.0;
  std::vector<std::string> methods = {"multilevel", "nbs"};
  long nbs_max_n = std::numeric_limits<long>::max();
  std::string json;
  int lanes = 0;  // 0: the default width
};

std::vector<std::string> splitList(const std::string& s) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (start <= s.size()) {
    const std::size_t comma = s.find(',', start);
    const std::size_t end = comma == std::string::npos ? s.size() : comma;
    if (end > start) parts.push_back(s.substr(start, end - start));
    start = end + 1;
  }
  return parts;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw Error("bench_broadphase: " + arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--n") {
      o.sizes.clear();
      for (const auto& p : splitList(value())) o.sizes.push_back(std::stoi(p));
    } else if (arg == "--layout") {
      o.scene.layout = value();
    } else if (arg == "--big-fraction") {
      o.scene.big_fraction = std::stod(value());
    } else if (arg == "--repeats") {
      o.repeats = std::stoi(value());
    } else if (arg == "--rounds") {
      o.rounds = std::stoi(value());
    } else if (arg == "--margin") {
      o.margin = std::stod(value());
    } else if (arg == "--shuffle") {
      o.scene.shuffle = true;
    } else if (arg == "--sort-cells") {
      o.scene.sort_cells = true;
    } else if (arg == "--lanes") {
      // Width of the sphere tests (default: the widest the CPU runs); 2 measures the SSE2 path.
      o.lanes = std::stoi(value());
      if (o.lanes != 2 && o.lanes != 4) throw Error("bench_broadphase: --lanes is 2 or 4");
    } else if (arg == "--ground") {
      o.scene.ground = true;
    } else if (arg == "--methods") {
      o.methods = splitList(value());
    } else if (arg == "--nbs-max-n") {
      o.nbs_max_n = std::stol(value());
    } else if (arg == "--json") {
      o.json = value();
    } else {
      throw Error("bench_broadphase: unknown option " + arg +
                  " (see the comment at the top of apps/bench_broadphase/main.cpp)");
    }
  }
  if (o.sizes.empty() || o.repeats < 1 || o.rounds < 1) {
    throw Error("bench_broadphase: need at least one N, --repeats >= 1, --rounds >= 1");
  }
  return o;
}

// CPU time of this thread: Zhao reports CPU time, and on a shared machine the wall clock also
// counts the time other processes hold the core.
double cpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct Timing {
  double cpu = std::numeric_limits<double>::infinity();   // seconds, fastest single detection
  double wall = std::numeric_limits<double>::infinity();  // seconds, the same detection
};

// Particles move a little between two detections, as between time steps: each detection gets the
// scene with every centre moved by up to `kStep` along each axis (fresh random moves each time,
// made outside the timed region), so that no detection repeats the one before bit for bit.
constexpr double kStep = 1e-4;  // m, 0.1 mm: small against the 2.5 mm gaps

class MovingScene {
 public:
  explicit MovingScene(const polydem::bench::CubeLayer& layer)
      : layer_(layer), centers_(layer.centers), rng_(7) {}
  SphereSet next() {
    for (std::size_t i = 0; i < centers_.size(); ++i) {
      centers_[i] = layer_.centers[i] + kStep * polydem::Vec3(unit(), unit(), unit());
    }
    return {centers_, layer_.radii, layer_.uids, layer_.active};
  }

 private:
  double unit() { return static_cast<double>(rng_() >> 11) * 0x1.0p-52 - 1.0; }  // [-1, 1)
  const polydem::bench::CubeLayer& layer_;
  std::vector<polydem::Vec3> centers_;
  std::mt19937_64 rng_;
};

// Warm-up (buffers sized, caches filled, clock raised) for at least 0.2 s, then `rounds` rounds
// of `repeats` detections, each timed alone. The fastest detection is kept: on a shared machine
// every slower one has had the core or the cache taken by something else.
Timing timeDetections(BroadPhase& bp, MovingScene& scene, const Options& o,
                      std::vector<CandidatePair>& out) {
  const double warm_start = cpuSeconds();
  do {
    bp.findPairs(scene.next(), o.margin, out);
  } while (cpuSeconds() - warm_start < 0.2);
  Timing best;
  for (int r = 0; r < o.rounds * o.repeats; ++r) {
    const SphereSet spheres = scene.next();
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = cpuSeconds();
    bp.findPairs(spheres, o.margin, out);
    const double cpu = cpuSeconds() - c0;
    const std::chrono::duration<double> wall = std::chrono::steady_clock::now() - t0;
    if (cpu < best.cpu) best = {cpu, wall.count()};
  }
  return best;
}

void sortPairs(std::vector<CandidatePair>& pairs) {
  std::sort(pairs.begin(), pairs.end(), [](const CandidatePair& a, const CandidatePair& b) {
    return a.i != b.i ? a.i < b.i : a.j < b.j;
  });
}

std::string levelsText(const BroadPhase& bp) {
  const auto* ml = dynamic_cast<const polydem::broadphase::MultiLevelGrid*>(&bp);
  if (ml == nullptr) return "";
  std::string text;
  for (const auto& l : ml->levels()) {
    char level[64];
    std::snprintf(level, sizeof level, "%s%d x %.3g m", text.empty() ? "" : " + ", l.count,
                  l.max_radius);
    text += level;
  }
  return text;
}

int run(const Options& o) {
  if (o.lanes != 0) {
    polydem::broadphase::detail::setTestLanes(
        static_cast<polydem::broadphase::detail::TestLanes>(o.lanes));
  }
  const auto& sc = o.scene;
  std::printf(
      "P-BROADPHASE (Zhao 5.5, table 7): cubes of 1.0 m and 0.1 m edge, %.0f%% big by "
      "count, layout '%s', %.1f mm gaps%s%s, margin %g m\n",
      100.0 * sc.big_fraction, sc.layout.c_str(), 1e3 * sc.gap,
      sc.shuffle ? ", storage order shuffled" : (sc.sort_cells ? ", storage in cell order" : ""),
      sc.ground ? ", ground slab" : "", o.margin);
  std::printf(
      "CPU time of one detection: the fastest of %d rounds of %d detections; ms/10 is "
      "ten times that; %d-lane sphere tests\n\n",
      o.rounds, o.repeats, static_cast<int>(polydem::broadphase::detail::testLanes()));
  std::printf("%8s %9s", "N", "pairs");
  for (const auto& m : o.methods) {
    std::printf(" | %10s %8s %8s %7s", (m + " ms").c_str(), "ms/10", "ns/part", "growth");
  }
  if (o.methods.size() == 2) std::printf(" | %7s", "ratio");
  std::printf(" | multilevel levels (count x largest radius)\n");

  nlohmann::json records = nlohmann::json::array();
  std::map<std::string, double> first_per_particle;
  for (const int n : o.sizes) {
    polydem::bench::CubeLayerSpec spec = sc;
    spec.n = n;
    const polydem::bench::CubeLayer layer = polydem::bench::makeCubeLayer(spec);
    const SphereSet spheres = layer.view();
    const double particles = static_cast<double>(layer.centers.size());
    std::vector<double> seconds;
    std::vector<CandidatePair> reference, out;
    std::string levels;
    std::size_t pairs = 0;
    for (const auto& m : o.methods) {
      if (m == "nbs" && n > o.nbs_max_n) {
        seconds.push_back(0.0);
        continue;
      }
      auto bp = polydem::broadphase::makeBroadPhase(m);
      MovingScene moving(layer);
      const Timing t = timeDetections(*bp, moving, o, out);
      const double s = t.cpu;
      seconds.push_back(s);
      bp->findPairs(spheres, o.margin, out);  // the scene as generated, to compare the methods
      if (levels.empty()) levels = levelsText(*bp);
      sortPairs(out);
      if (reference.empty()) {
        reference = out;
      } else if (out != reference) {
        throw Error(polydem::cat("bench_broadphase: ", m, " found ", out.size(),
                                 " pairs, the first method ", reference.size(), " (N = ", n, ")"));
      }
      pairs = out.size();
      records.push_back({{"n", n},
                         {"method", m},
                         {"seconds_per_detection", s},
                         {"wall_seconds_per_detection", t.wall},
                         {"pairs", out.size()},
                         {"ns_per_particle", 1e9 * s / particles},
                         {"layout", sc.layout},
                         {"big_fraction", sc.big_fraction},
                         {"ground", sc.ground},
                         {"shuffled", sc.shuffle},
                         {"sorted_cells", sc.sort_cells},
                         {"lanes", static_cast<int>(polydem::broadphase::detail::testLanes())}});
    }
    std::printf("%8d %9zu", n, pairs);
    for (std::size_t k = 0; k < o.methods.size(); ++k) {
      if (seconds[k] == 0.0) {
        std::printf(" | %10s %8s %8s %7s", "-", "-", "-", "-");
        continue;
      }
      const double per_particle = 1e9 * seconds[k] / particles;
      auto [it, inserted] = first_per_particle.emplace(o.methods[k], per_particle);
      std::printf(" | %10.3f %8.2f %8.1f %7.2f", 1e3 * seconds[k], 1e4 * seconds[k], per_particle,
                  per_particle / it->second);
    }
    if (o.methods.size() == 2) {
      if (seconds[0] > 0.0 && seconds[1] > 0.0) {
        std::printf(" | %7.2f", seconds[1] / seconds[0]);
      } else {
        std::printf(" | %7s", "-");
      }
    }
    std::printf(" | %s\n", levels.c_str());
    std::fflush(stdout);
  }
  std::printf(
      "\nms/10: ten detections, as in Zhao figs. 43-44; growth: time per particle / that at "
      "the first N; ratio: %s / %s\n",
      o.methods.size() == 2 ? o.methods[1].c_str() : "-",
      o.methods.size() == 2 ? o.methods[0].c_str() : "-");
  if (!o.json.empty()) {
    std::ofstream file(o.json);
    file << records.dump(1) << "\n";
    if (!file) throw Error("bench_broadphase: cannot write " + o.json);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(parse(argc, argv));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_broadphase: %s\n", e.what());
    return 1;
  }
}

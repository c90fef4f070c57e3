// A user force operator on an installed polydem (see CMakeLists.txt): two cubes fall freely; an
// operator lifts the second with half its weight (a buoyancy, say), so it falls at g/2. The
// leapfrog integrates a constant acceleration exactly, so after n steps each cube must be where
// z(t) = z0 + v0 t + a t^2 / 2 puts it, to rounding. Prints both drops against their analytical
// values and exits 1 on a mismatch (any rank count: `mpiexec -n 2 force_operator`).
#include <mpi.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "polydem/core/mpi_env.h"
#include "polydem/geometry/shapes.h"
#include "polydem/setup/setup.h"
#include "polydem/sim/simulation.h"

namespace {

using polydem::Vec3;

constexpr double kG = 9.81;
constexpr double kDt = 1e-4;
constexpr int kSteps = 2000;
constexpr double kHeight = 5.0;
constexpr polydem::Uid kLifted = 2;

polydem::setup::Setup twoFallingCubes() {
  polydem::setup::Setup scene;
  scene.file = "<force_operator example>";
  scene.dt = kDt;
  scene.steps = kSteps;
  scene.gravity = Vec3(0, 0, -kG);
  polydem::particles::Material rock;
  rock.name = "rock";
  rock.density = 2650;
  rock.kn = 1e8;
  rock.ks = 5e7;
  rock.friction_angle = 30;
  rock.penalty = 1e9;  // no local damping: the fall is free
  scene.materials.push_back(rock);
  scene.shapes.push_back(
      {"cube", polydem::geometry::shapes::box(Vec3(-0.5, -0.5, -0.5), Vec3(0.5, 0.5, 0.5)), 0});
  for (polydem::Uid uid : {polydem::Uid{1}, kLifted}) {
    polydem::setup::ParticleSpec p;
    p.uid = uid;
    p.shape = 0;
    p.material = 0;
    p.position = Vec3(uid == 1 ? -3.0 : 3.0, 0.0, kHeight);
    scene.particles.push_back(p);
  }
  scene.domain.min = Vec3(-10, -10, -10);
  scene.domain.max = Vec3(10, 10, 10);
  return scene;
}

}  // namespace

int main(int argc, char** argv) {
  polydem::mpi::Environment env(argc, argv);
  int failures = 0, checked = 0;
  try {
    polydem::sim::Simulation sim(twoFallingCubes(), MPI_COMM_WORLD);
    // The user's force: half the weight of particle kLifted, upwards, at its centroid.
    sim.addForceOperator("uplift", [](const polydem::sim::ForceStep& step) {
      for (std::size_t i = 0; i < step.forces.size(); ++i) {
        if ((*step.particles)[i].uid != kLifted) continue;
        step.forces[i].addBodyForce(Vec3(0, 0, 0.5 * kG * step.particles->mass(i)));
      }
    });
    sim.run();
    const double t = sim.time();
    const auto& storage = sim.particles();
    for (std::size_t i = 0; i < storage.localCount(); ++i) {
      const auto& p = storage[i];
      const double a = p.uid == kLifted ? 0.5 * kG : kG;
      const double expected = 0.5 * a * t * t;
      const double drop = kHeight - p.position.z();
      const bool ok = std::abs(drop - expected) <= 1e-9 * expected;
      std::printf(
          "particle %llu: dropped %.12f m in %.4f s, analytical %.12f m (a = %.4f m/s^2) %s\n",
          static_cast<unsigned long long>(p.uid), drop, t, expected, a, ok ? "ok" : "MISMATCH");
      failures += ok ? 0 : 1;
      ++checked;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "force_operator: %s\n", e.what());
    failures = 1;
  }
  int counts[2] = {failures, checked}, totals[2] = {0, 0};
  MPI_Allreduce(counts, totals, 2, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  if (totals[1] != 2) {  // every cube is owned by exactly one rank
    std::fprintf(stderr, "force_operator: %d particles checked, expected 2\n", totals[1]);
    return EXIT_FAILURE;
  }
  return totals[0] == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}

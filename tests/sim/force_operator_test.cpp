// Simulation::addForceOperator (sim/force_operator.h): a user force reaches the integrator, on any
// rank count, and an operator that adds nothing changes no bit.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "polydem/core/error.h"
#include "polydem/geometry/shapes.h"
#include "polydem/setup/setup.h"
#include "polydem/sim/simulation.h"

namespace polydem::sim {
namespace {

constexpr double kG = 9.81;
constexpr double kHeight = 5.0;

// Cubes falling freely in a row (no contacts), spread so that several ranks own some.
setup::Setup fallingCubes(int count) {
  setup::Setup s;
  s.file = "<force operator test>";
  s.dt = 1e-4;
  s.steps = 400;
  s.gravity = Vec3(0, 0, -kG);
  particles::Material rock;
  rock.name = "rock";
  rock.density = 2650;
  rock.kn = 1e8;
  rock.ks = 5e7;
  rock.penalty = 1e9;
  s.materials.push_back(rock);
  s.shapes.push_back(
      {"cube", geometry::shapes::box(Vec3(-0.5, -0.5, -0.5), Vec3(0.5, 0.5, 0.5)), 0});
  for (int i = 0; i < count; ++i) {
    setup::ParticleSpec p;
    p.uid = static_cast<Uid>(i + 1);
    p.shape = 0;
    p.material = 0;
    p.position = Vec3(-9.0 + 3.0 * i, 0.0, kHeight);
    s.particles.push_back(p);
  }
  s.domain.min = Vec3(-10, -10, -10);
  s.domain.max = Vec3(10, 10, 10);
  return s;
}

// Particle uid u is lifted by u / 10 of its weight: it falls at g (1 - u / 10).
void liftByUid(const ForceStep& step) {
  for (std::size_t i = 0; i < step.forces.size(); ++i) {
    const auto& p = (*step.particles)[i];
    step.forces[i].addBodyForce(
        Vec3(0, 0, 0.1 * static_cast<double>(p.uid) * kG * step.particles->mass(i)));
  }
}

TEST(ForceOperator, EveryParticleFallsAtItsOwnAcceleration) {
  Simulation sim(fallingCubes(6), MPI_COMM_WORLD);
  sim.addForceOperator("lift", liftByUid);
  sim.run();
  const double t = sim.time();
  ASSERT_NEAR(t, 0.04, 1e-12);
  int checked = 0;
  for (std::size_t i = 0; i < sim.particles().localCount(); ++i) {
    const auto& p = sim.particles()[i];
    const double a = kG * (1.0 - 0.1 * static_cast<double>(p.uid));
    const double expected = 0.5 * a * t * t;  // exact for the leapfrog under constant forces
    EXPECT_NEAR(kHeight - p.position.z(), expected, 1e-10 * expected) << "uid " << p.uid;
    ++checked;
  }
  int total = 0;
  MPI_Allreduce(&checked, &total, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(total, 6);
}

TEST(ForceOperator, AnOperatorAddingNothingChangesNoBit) {
  Simulation plain(fallingCubes(6), MPI_COMM_WORLD);
  plain.run();
  Simulation with(fallingCubes(6), MPI_COMM_WORLD);
  int calls = 0;
  with.addForceOperator("nothing", [&](const ForceStep& step) {
    ++calls;
    for (auto& f : step.forces) f.addBodyForce(Vec3::Zero());
  });
  with.run();
  EXPECT_EQ(calls, 401);  // the leapfrog's start and every step
  EXPECT_EQ(plain.stateHash().hex(), with.stateHash().hex());
}

TEST(ForceOperator, OperatorsRunInOrderAndNeedNewNames) {
  Simulation sim(fallingCubes(1), MPI_COMM_WORLD);
  sim.addForceOperator("first", [](const ForceStep&) {});
  sim.addForceOperator("second", [](const ForceStep&) {});
  EXPECT_EQ(sim.forceOperatorNames(), (std::vector<std::string>{"first", "second"}));
  EXPECT_THROW(sim.addForceOperator("first", [](const ForceStep&) {}), Error);
  EXPECT_THROW(sim.addForceOperator("", [](const ForceStep&) {}), Error);
  EXPECT_THROW(sim.addForceOperator("empty", ForceOperator{}), Error);
}

// The timer names of the loop, in the order they were first used (the order of the step).
std::vector<std::string> timerNames(Simulation& sim) {
  std::vector<std::string> names;
  for (const auto& e : sim.loop().timing().entries()) names.push_back(e.name);
  return names;
}

TEST(ForceOperator, EachOperatorIsTimedUnderItsNameWithinTheStep) {
  Simulation sim(fallingCubes(2), MPI_COMM_WORLD);
  sim.addForceOperator("lift", liftByUid);
  sim.step();  // added later: after "lift", before the force ratio, from the next step on
  sim.addForceOperator("drag", [](const ForceStep&) {});
  sim.step();
  sim.step();
  const auto names = timerNames(sim);
  const auto at = [&](const std::string& name) {
    return std::find(names.begin(), names.end(), name) - names.begin();
  };
  ASSERT_LT(at("lift"), static_cast<std::ptrdiff_t>(names.size()));
  ASSERT_LT(at("drag"), static_cast<std::ptrdiff_t>(names.size()));
  // Gravity, the user's forces and the force ratio each under their own timer, not "contacts".
  EXPECT_LT(at("contacts"), at("body forces"));
  EXPECT_LT(at("body forces"), at("lift"));
  EXPECT_LT(at("lift"), at("force ratio"));
  EXPECT_LT(at("force ratio"), at("integrate"));
  for (const auto& e : sim.loop().timing().entries()) {
    if (e.name == "lift") {
      EXPECT_EQ(e.count, 3);
    }
    if (e.name == "drag") {
      EXPECT_EQ(e.count, 2);
    }
  }
  // A step operator's name is taken: the timing table would merge the two.
  EXPECT_THROW(sim.addForceOperator("water", [](const ForceStep&) {}), Error);
  EXPECT_THROW(sim.addForceOperator("contacts", [](const ForceStep&) {}), Error);
}

TEST(ForceOperator, AnOperatorAddedLaterRunsAfterTheEarlierOnes) {
  Simulation sim(fallingCubes(1), MPI_COMM_WORLD);
  std::vector<std::string> calls;
  sim.addForceOperator("first", [&](const ForceStep&) { calls.push_back("first"); });
  sim.step();
  sim.addForceOperator("second", [&](const ForceStep&) { calls.push_back("second"); });
  calls.clear();
  sim.step();
  EXPECT_EQ(calls, (std::vector<std::string>{"first", "second"}));
}

TEST(ForceOperator, AnOperatorCannotStepChangeOrCheckpointItsSimulation) {
  // Every such call from inside the operator throws, naming it, and changes nothing: the run
  // ends with the bits of one whose operator tried none.
  Simulation sim(fallingCubes(6), MPI_COMM_WORLD);
  int refused = 0;
  const auto expectRefused = [&](const char* what, const std::function<void()>& call) {
    try {
      call();
      ADD_FAILURE() << what << " was taken inside the operator";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(std::string(what) + " called from inside force " +
                                           "operator 'meddles'"),
                std::string::npos)
          << e.what();
      ++refused;
    }
  };
  sim.addForceOperator("meddles", [&](const ForceStep&) {
    expectRefused("step", [&] { sim.step(); });
    expectRefused("run", [&] { sim.run(); });
    expectRefused("runEquilibrium", [&] { sim.runEquilibrium(); });
    expectRefused("setVelocity", [&] { sim.setVelocity(1, Vec3(1, 0, 0), std::nullopt); });
    expectRefused("addForceOperator", [&] { sim.addForceOperator("x", [](const ForceStep&) {}); });
    expectRefused("checkpoint", [&] { sim.checkpoint("", "", ""); });
    expectRefused("rebalance", [&] { sim.rebalance(); });
    expectRefused("reorderParticles", [&] { sim.reorderParticles({}); });
  });
  sim.run();
  EXPECT_EQ(refused, 8 * 401);  // the leapfrog's start and every step
  Simulation plain(fallingCubes(6), MPI_COMM_WORLD);
  plain.addForceOperator("nothing", [](const ForceStep&) {});
  plain.run();
  EXPECT_EQ(plain.stateHash().hex(), sim.stateHash().hex());
  // Between steps the same calls are taken again.
  EXPECT_NO_THROW(sim.checkpoint("", "", ""));
}

}  // namespace
}  // namespace polydem::sim

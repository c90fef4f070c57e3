// Bindings of sim::Simulation: step a scene from Python and read the particle state as numpy
// arrays. All ranks of its communicator take part; the collective methods are marked so.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "bindings.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/dynamics/driver.h"
#include "polydem/dynamics/integrator.h"
#include "polydem/scene/scene_reader.h"
#include "polydem/setup/setup.h"
#include "polydem/sim/simulation.h"

namespace polydem::python {

namespace {

using sim::Simulation;

// One particle as particles() reports it; plain data, so it can be gathered as bytes.
struct ParticleRow {
  Uid uid = 0;
  std::int32_t shape = -1, material = -1;
  std::uint32_t flags = 0;
  double position[3], orientation[4], velocity[3], angular_velocity[3];
};

// The angular velocity of local particle i in the leapfrog's convention: free particles from their
// angular momentum (half step t - dt/2) and orientation, driven ones their driver's w at t - dt/2.
Vec3 angularVelocity(const Simulation& sim, std::size_t i) {
  const auto& p = sim.particles()[i];
  if (p.isFree()) {
    return dynamics::angularVelocity(p.orientation, p.angular_momentum,
                                     sim.massProperties(i).principal_inertia);
  }
  if (p.isDriven() && sim.stage() == sim::Stage::kMain) {
    const double t_half = sim.time() - 0.5 * sim.dt();
    return dynamics::driverState(sim.scene().drivers[p.driver], t_half).angular_velocity;
  }
  return Vec3::Zero();
}

ParticleRow rowOf(const Simulation& sim, std::size_t i) {
  const auto& p = sim.particles()[i];
  ParticleRow r;
  r.uid = p.uid;
  r.shape = p.shape;
  r.material = p.material;
  r.flags = p.flags;
  const Vec3 w = angularVelocity(sim, i);
  const double q[4] = {p.orientation.w(), p.orientation.x(), p.orientation.y(), p.orientation.z()};
  for (int k = 0; k < 3; ++k) {
    r.position[k] = p.position[k];
    r.velocity[k] = p.velocity[k];
    r.angular_velocity[k] = w[k];
  }
  std::copy(q, q + 4, r.orientation);
  return r;
}

// The scene's labels of `rows` ("" where none): the reader numbers particles 1, 2, ... in scene
// order, so uid u is entry u - 1 of the scene's list.
py::list labelsOf(const setup::Setup& scene, const std::vector<ParticleRow>& rows) {
  py::list labels;
  for (const ParticleRow& r : rows) {
    const bool known =
        r.uid >= 1 && r.uid <= scene.particles.size() && scene.particles[r.uid - 1].uid == r.uid;
    labels.append(known ? scene.particles[r.uid - 1].label : std::string());
  }
  return labels;
}

py::dict particleArrays(const Simulation& sim, bool gather) {
  const auto& storage = sim.particles();
  const bool root = mpi::rank(sim.comm()) == 0;
  std::vector<ParticleRow> rows;
  for (std::size_t i = 0; i < storage.localCount(); ++i) {
    // Fixed and driven bodies are replicated on every rank: gathered, rank 0's copy stands.
    if (gather && storage[i].isGlobal() && !root) continue;
    rows.push_back(rowOf(sim, i));
  }
  if (gather) rows = mpi::allgatherv(rows, sim.comm());
  std::sort(rows.begin(), rows.end(),
            [](const ParticleRow& a, const ParticleRow& b) { return a.uid < b.uid; });

  const auto n = static_cast<py::ssize_t>(rows.size());
  auto uid = emptyArray<std::uint64_t>({n});
  auto shape = emptyArray<std::int32_t>({n});
  auto material = emptyArray<std::int32_t>({n});
  auto flags = emptyArray<std::uint32_t>({n});
  auto position = emptyArray<double>({n, 3});
  auto orientation = emptyArray<double>({n, 4});
  auto velocity = emptyArray<double>({n, 3});
  auto angular_velocity = emptyArray<double>({n, 3});
  for (py::ssize_t i = 0; i < n; ++i) {
    const ParticleRow& r = rows[i];
    uid.mutable_data()[i] = r.uid;
    shape.mutable_data()[i] = r.shape;
    material.mutable_data()[i] = r.material;
    flags.mutable_data()[i] = r.flags;
    std::copy(r.position, r.position + 3, position.mutable_data() + 3 * i);
    std::copy(r.orientation, r.orientation + 4, orientation.mutable_data() + 4 * i);
    std::copy(r.velocity, r.velocity + 3, velocity.mutable_data() + 3 * i);
    std::copy(r.angular_velocity, r.angular_velocity + 3, angular_velocity.mutable_data() + 3 * i);
  }
  py::dict d;
  d["uid"] = uid;
  d["position"] = position;
  d["orientation"] = orientation;
  d["velocity"] = velocity;
  d["angular_velocity"] = angular_velocity;
  d["shape"] = shape;
  d["material"] = material;
  d["flags"] = flags;
  d["label"] = labelsOf(sim.scene(), rows);
  return d;
}

py::dict contactArrays(const Simulation& sim) {
  std::vector<const sim::ContactRecord*> touching;
  for (const auto& r : sim.contacts().records()) {
    if (r.touching && r.a_is_local) touching.push_back(&r);
  }
  const auto n = static_cast<py::ssize_t>(touching.size());
  auto uids = emptyArray<std::uint64_t>({n, 2});
  auto point = emptyArray<double>({n, 3});
  auto normal = emptyArray<double>({n, 3});
  auto force = emptyArray<double>({n, 3});
  auto normal_force = emptyArray<double>({n});
  auto shear_force = emptyArray<double>({n});
  auto joint = emptyArray<std::int32_t>({n});
  for (py::ssize_t i = 0; i < n; ++i) {
    const auto& r = *touching[i];
    uids.mutable_data()[2 * i] = r.key.lo;
    uids.mutable_data()[2 * i + 1] = r.key.hi;
    for (int k = 0; k < 3; ++k) {
      point.mutable_data()[3 * i + k] = r.point[k];
      normal.mutable_data()[3 * i + k] = r.normal[k];
      force.mutable_data()[3 * i + k] = r.force[k];
    }
    normal_force.mutable_data()[i] = r.normal_force;
    shear_force.mutable_data()[i] = r.shear_force;
    joint.mutable_data()[i] = r.joint;
  }
  py::dict d;
  d["uids"] = uids;
  d["point"] = point;
  d["normal"] = normal;
  d["force"] = force;
  d["normal_force"] = normal_force;
  d["shear_force"] = shear_force;
  d["joint"] = joint;
  return d;
}

py::dict monitors(Simulation& sim) {
  const sim::GlobalMonitors g = sim.monitors();
  py::dict d;
  d["time"] = sim.time();
  d["step"] = sim.stepCount();
  d["kinetic_energy"] = g.kinetic_energy;
  d["force_ratio"] = g.force_ratio;
  d["contacts"] = g.contacts;
  d["particles"] = g.particles;
  d["max_speed"] = g.max_speed;
  d["mean_speed"] = g.mean_speed;
  return d;
}

void step(Simulation& sim, std::int64_t n) {
  sim.requireBetweenSteps("Simulation.step");
  if (n < 0) throw py::value_error(cat("step count must be >= 0, got ", n));
  for (std::int64_t k = 0; k < n; ++k) {
    sim.step();
    checkSignals();  // between steps: the state stays whole
  }
}

const char* run(Simulation& sim) {
  sim.requireBetweenSteps("Simulation.run");
  if (!sim.scene().end_time && !sim.scene().steps) {
    throw py::value_error("the scene has neither end_time nor steps: nothing tells run() to stop");
  }
  // Ctrl-C ends the run after the step it arrives in (on every rank: the loop requires the
  // condition to agree, which it does when mpirun forwards the signal to all of them).
  sim.loop().stopWhen("interrupt", [] { return PyErr_CheckSignals() != 0; });
  const auto reason = sim.run();
  if (PyErr_Occurred()) throw py::error_already_set();
  return timeloop::toString(reason);
}

// A force an operator returned for particle `uid`: finite, and not so large that it alone would
// move the particle farther than `reach` (Simulation::stepReach) in one step: |F| dt^2 / m.
void checkForce(const Vec3& f, Uid uid, double mass, double dt, double reach,
                const std::string& name) {
  const double moves = f.norm() / mass * dt * dt;
  if (f.allFinite() && moves <= reach) return;
  throw py::value_error(
      cat("force operator '", name, "' returned the force (", f.transpose(), ") N for particle ",
          uid, ", which ",
          f.allFinite() ? cat("would move it ", moves, " m in one step (|F| dt^2 / m, m = ", mass,
                              " kg, dt = ", dt, " s), more than ", reach,
                              " m, the farthest a particle may move in one step")
                        : std::string("is not finite")));
}

void addPythonForceOperator(Simulation& sim, const std::string& name, py::object fn) {
  sim.requireBetweenSteps("Simulation.add_force_operator");
  sim.addForceOperator(name, pythonForceOperator(name, std::move(fn)));
}

}  // namespace

// A Python force operator: fn(time, dt, particles) -> forces, with `particles` a dict of numpy
// arrays of this rank's own particles (uid, position, velocity, mass, free) and `forces` an
// (n, 3) array-like (or None: no force). The forces are added at the centroids of the free ones.
sim::ForceOperator pythonForceOperator(const std::string& name, py::object fn) {
  if (!PyCallable_Check(fn.ptr())) {
    throw py::type_error(cat("force operator '", name, "' is not given a callable"));
  }
  return [fn = std::move(fn), name](const sim::ForceStep& step) {
    const auto& storage = *step.particles;
    const auto n = static_cast<py::ssize_t>(step.forces.size());
    auto uid = emptyArray<std::uint64_t>({n});
    auto position = emptyArray<double>({n, 3});
    auto velocity = emptyArray<double>({n, 3});
    auto mass = emptyArray<double>({n});
    auto free = emptyArray<bool>({n});
    for (py::ssize_t i = 0; i < n; ++i) {
      const auto& p = storage[static_cast<std::size_t>(i)];
      uid.mutable_at(i) = p.uid;
      mass.mutable_at(i) = storage.mass(static_cast<std::size_t>(i));
      free.mutable_at(i) = p.isFree();
      for (py::ssize_t k = 0; k < 3; ++k) {
        position.mutable_at(i, k) = p.position[k];
        velocity.mutable_at(i, k) = p.velocity[k];
      }
    }
    py::dict particles;
    particles["uid"] = uid;
    particles["position"] = position;
    particles["velocity"] = velocity;
    particles["mass"] = mass;
    particles["free"] = free;
    const py::object result = fn(step.time, step.dt, particles);
    if (result.is_none() || n == 0) return;
    const auto forces =
        toPoints(result, cat("forces returned by force operator '", name, "'").c_str());
    if (static_cast<py::ssize_t>(forces.size()) != n) {
      throw py::value_error(cat("force operator '", name, "' returned ", forces.size(),
                                " forces for ", n, " particles"));
    }
    for (std::size_t i = 0; i < forces.size(); ++i) {
      if (!storage[i].isFree()) continue;
      checkForce(forces[i], storage[i].uid, storage.mass(i), step.dt, step.reach, name);
      step.forces[i].addBodyForce(forces[i]);
    }
  };
}

sim::HostOperators pythonOperators(const py::object& operators) {
  sim::HostOperators host;
  if (operators.is_none()) return host;
  if (!py::isinstance<py::dict>(operators)) {
    throw py::type_error("operators must be a dict {name: fn} or None");
  }
  for (const auto& [key, fn] : operators.cast<py::dict>()) {
    const std::string name = py::str(key);
    host[name] = pythonForceOperator(name, py::reinterpret_borrow<py::object>(fn));
  }
  return host;
}

void bindSimulation(py::module_& m) {
  m.attr("FLAG_GHOST") = static_cast<std::uint32_t>(particles::kGhost);
  m.attr("FLAG_FIXED") = static_cast<std::uint32_t>(particles::kFixed);
  m.attr("FLAG_DRIVEN") = static_cast<std::uint32_t>(particles::kDriven);

  py::class_<Simulation> simulation(
      m, "Simulation",
      R"(A run of a scene on the ranks of a communicator, stepped from Python.

Built from a Scene (or a scene file's path) as `polydem run` builds it; step(n) advances it, the
state is read with particles(), contacts(), monitors() and state_hash(). On several ranks
(mpirun -n N python script.py) every rank must make the same calls in the same order: methods
marked "collective" talk to the other ranks.

The state follows polydem's leapfrog: positions and orientations at `time`, velocities at
time - dt/2. `position` is the centroid and `orientation` turns the shape's body frame (its
principal axes, see `shapes`) into the world.

Simulation(scene, comm=None, operators=None): `scene` is a polydem.Scene built in Python, a
SceneData read with read_scene, or the path of a scene file; `comm` None (MPI_COMM_WORLD) or an
mpi4py communicator (its ranks run the simulation; every rank of it must build it); `operators` a
dict {name: fn} of force operators (fn as for add_force_operator) for the scene's [[operator]]s
that name no library: each runs at the scene's place for it, timed under its name.)");
  simulation
      .def(py::init(&makeSimulation), py::arg("scene"), py::arg("comm") = py::none(),
           py::arg("operators") = py::none(), py::keep_alive<1, 3>(),
           "Builds the simulation of `scene` on `comm` (collective).")
      .def("step", &step, py::arg("n") = 1,
           "Advances `n` steps of the current stage (collective). Ctrl-C stops between steps.")
      .def("run", &run,
           "Runs the main stage to the scene's end time or step count (collective); returns why\n"
           "it stopped ('end time', 'step limit', ...).")
      .def(
          "run_equilibrium",
          [](Simulation& s) {
            s.requireBetweenSteps("Simulation.run_equilibrium");
            return s.runEquilibrium();
          },
          "Runs the initial-equilibrium stage if the scene has one (collective); returns its step\n"
          "count (0 without one). Call it before stepping the main stage, as polydem run does.")
      .def("add_force_operator", &addPythonForceOperator, py::arg("name"), py::arg("fn"),
           R"(Adds a force to every later step (sim/force_operator.h): fn(time, dt, particles)
is called on every rank after the contact forces and gravity, before integration, with this
rank's own particles as a dict of numpy arrays: uid (n,), position (n, 3) [m] at `time`,
velocity (n, 3) [m/s] at time - dt/2, mass (n,) [kg], free (n,) bool. It returns an (n, 3)
array of forces [N] acting at the centroids (entries of particles that are not free are
ignored), or None. `name` must be new. Added before the first step (collective then), fn is
also called at once, for its share of the leapfrog's start. Exceptions from fn end the step (or
the call adding it) with that error; so does a force that is not finite or would alone move its
particle more than `step_reach` in one step (|F| dt^2 / m). fn must not step, change or
checkpoint the simulation (step, run, set_velocity, add_force_operator, write_checkpoint raise
polydem.Error when called from fn): its step is half done.)")
      .def_property_readonly("force_operators", method(&Simulation::forceOperatorNames),
                             "Names of the force operators, in the order they run.")
      .def_property_readonly("time", method(&Simulation::time), "Simulated time [s].")
      .def_property_readonly("step_count", method(&Simulation::stepCount),
                             "Steps taken in this stage.")
      .def_property_readonly("dt", method(&Simulation::dt), "Time step [s].")
      .def_property_readonly(
          "stage",
          [](const Simulation& s) {
            return s.stage() == sim::Stage::kEquilibrium ? "equilibrium" : "main";
          },
          "'equilibrium' or 'main'.")
      .def_property_readonly("suggested_time_step", method(&Simulation::suggestedTimeStep),
                             "The dt suggested by masses and stiffnesses [s].")
      .def_property_readonly(
          "step_reach", method(&Simulation::stepReach),
          "The farthest any point of a particle may move in one step [m]: the largest free\n"
          "circumradius plus the contact margin (set_velocity and force operators are held to it).")
      .def_property_readonly(
          "scene", [](const Simulation& s) { return s.scene(); },
          "A copy of the scene the simulation was built from.")
      .def_property_readonly(
          "shapes",
          [](const Simulation& s) {
            std::vector<geometry::ConvexPolyhedron> out;
            for (const auto& shape : s.shapes()) out.push_back(*shape.polyhedron);
            return out;
          },
          "The shape table in body frames (centroid at the origin, principal axes), indexed by\n"
          "particles()['shape']: world vertices = position + R(orientation) @ vertex.")
      .def("particles", &particleArrays, py::arg("gather") = false,
           R"(The particle state as a dict of numpy arrays, sorted by uid.

uid (n,) uint64, position (n, 3) [m], orientation (n, 4) unit quaternions (w, x, y, z),
velocity (n, 3) [m/s], angular_velocity (n, 3) [rad/s], shape and material (n,) int32 indices,
flags (n,) uint32 (polydem.FLAG_FIXED, FLAG_DRIVEN), label (list of n str, "" for none).
Without `gather`, this rank's local particles: those it owns plus the fixed and driven bodies
every rank holds. With gather=True (collective), every particle of the simulation once, on every
rank.)")
      .def("contacts", &contactArrays,
           R"(The touching contacts of the last step whose lower-uid particle is local to this rank.

uids (n, 2) (lower, higher), point (n, 3), normal (n, 3) (from the higher into the lower uid),
force (n, 3) on the lower-uid particle [N], normal_force, shear_force (n,) [N], joint (n,) int32:
the index into the scene's [[joint]] list of the joint whose properties the contact took, -1 for
the material pair's.)")
      .def("monitors", &monitors,
           "Global values (collective): time, step, kinetic_energy [J], force_ratio (Keissar\n"
           "eq. 3.2), contacts, particles (free ones), max_speed, mean_speed [m/s].")
      .def(
          "state_hash", [](const Simulation& s) { return s.stateHash().hex(); },
          "Hash of the whole state (collective), the same on any rank count; equal to the\n"
          "state_hash `polydem run` writes to summary.json after the same steps.")
      .def("__repr__", [](const Simulation& s) {
        return cat("Simulation('", s.scene().id, "', step ", s.stepCount(), ", t = ", num(s.time()),
                   " s)");
      });
  bindSimulationCheckpoint(simulation);
}

}  // namespace polydem::python

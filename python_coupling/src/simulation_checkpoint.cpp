// Simulation from Python beyond stepping: building one from any scene (a Scene read from a file,
// a polydem.Scene built in Python, a path) on any communicator, writing a checkpoint and
// continuing from one (docs/checkpoint.md). A checkpoint stores the scene's TOML text
// (setup::Setup::text), which is how a scene built in Python, without a file, can be restarted.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bindings.h"
#include "polydem/checkpoint/checkpoint.h"
#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/run/checks.h"
#include "polydem/run/run_checkpoint.h"
#include "polydem/run/tracker.h"
#include "polydem/scene/scene_reader.h"
#include "polydem/setup/setup.h"
#include "polydem/sim/simulation.h"

namespace polydem::python {

namespace {

using sim::Simulation;

std::string fspath(const py::object& path, const char* what) {
  if (!py::isinstance<py::str>(path) && !py::hasattr(path, "__fspath__")) {
    throw py::type_error(cat(what, " must be a str or os.PathLike, got ",
                             py::str(py::type::of(path).attr("__name__")).cast<std::string>()));
  }
  return py::module_::import("os").attr("fspath")(path).cast<std::string>();
}

void writeCheckpoint(const Simulation& sim, const py::object& path_object) {
  sim.requireBetweenSteps("Simulation.write_checkpoint");
  const std::string path = fspath(path_object, "path");
  if (sim.scene().text.empty()) {
    throw py::value_error("the simulation's scene has no TOML text to store in a checkpoint");
  }
  // A run from Python has no checks or monitors of its own: its run state holds the kernel and
  // contact model, which may have been set over the scene text's.
  const run::Tracker tracker;
  const std::vector<std::unique_ptr<run::Check>> checks;
  sim::CheckpointData data = sim.checkpointForWriting(
      sim.scene().text, sim.scene().file, run::runStateJson(sim.scene(), tracker, checks));
  data.code_version = POLYDEM_VERSION;
  checkpoint::writeCheckpoint(path, data, sim.comm());
}

std::unique_ptr<Simulation> restart(const py::object& path_object, const py::object& comm_object,
                                    const py::object& operators) {
  const std::string path = fspath(path_object, "path");
  const MPI_Comm comm = toComm(comm_object);
  checkpoint::CheckpointReader reader(path, comm);  // the pair histories in chunks
  const sim::CheckpointData& data = reader.data();
  setup::Setup scene = scene::parseScene(data.scene_toml, data.scene_file);
  run::prepareContinuation(data, path, scene);
  return std::make_unique<Simulation>(scene, data, reader, path, comm, pythonOperators(operators));
}

// A finite 3-vector or nothing (None).
std::optional<Vec3> optionalVec3(const py::object& object, const char* what) {
  if (object.is_none()) return std::nullopt;
  const Vec3 v = toVec3(object, what);
  if (!v.allFinite()) throw py::value_error(cat(what, " must be finite"));
  return v;
}

void setVelocity(Simulation& sim, std::int64_t uid, const py::object& velocity,
                 const py::object& angular_velocity) {
  sim.requireBetweenSteps("Simulation.set_velocity");
  const auto v = optionalVec3(velocity, "velocity");
  const auto w = optionalVec3(angular_velocity, "angular_velocity");
  if (uid <= 0) throw py::value_error(cat("uid must be positive, got ", uid));
  bool found = false;
  try {
    found = sim.setVelocity(static_cast<Uid>(uid), v, w);
  } catch (const SimulationError&) {
    throw;
  } catch (const Error& e) {  // a refused value, on every rank
    throw py::value_error(cat("set_velocity: ", e.what()));
  }
  if (!found) {
    throw py::value_error(
        cat("no free particle has uid ", uid, " (fixed and driven bodies move as the scene says)"));
  }
}

}  // namespace

std::unique_ptr<Simulation> makeSimulation(const py::object& scene, const py::object& comm_object,
                                           const py::object& operators) {
  const MPI_Comm comm = toComm(comm_object);
  const sim::HostOperators host = pythonOperators(operators);
  if (py::isinstance<setup::Setup>(scene)) {
    return std::make_unique<Simulation>(scene.cast<const setup::Setup&>(), comm, host);
  }
  if (py::hasattr(scene, "build") && py::hasattr(scene, "to_toml")) {  // polydem.Scene
    const py::object built = scene.attr("build")();
    if (!py::isinstance<setup::Setup>(built))
      throw py::type_error("Scene.build() returned no scene");
    return std::make_unique<Simulation>(built.cast<const setup::Setup&>(), comm, host);
  }
  return std::make_unique<Simulation>(scene::readScene(fspath(scene, "scene")), comm, host);
}

void bindSimulationCheckpoint(py::class_<Simulation>& c) {
  c.def("write_checkpoint", &writeCheckpoint, py::arg("path"),
        R"(Writes a checkpoint of the current state to `path` (collective; docs/checkpoint.md).

The file holds the scene's TOML text and everything needed to continue bit for bit, on this or
any other number of ranks: Simulation.restart(path). Call it between steps. It is written under a
temporary name next to `path` and renamed onto it when complete, so `path` must be new, an empty
file or a polydem checkpoint (replaced); a symbolic link is followed. Raises
polydem.CheckpointError, naming the path, for anything else (a FIFO, a device such as /dev/null, a
directory, a file that is not a polydem checkpoint), which is left as it was, and if the file
cannot be written (an older file at `path` is kept).)")
      .def("set_velocity", &setVelocity, py::arg("uid"), py::arg("velocity") = py::none(),
           py::arg("angular_velocity") = py::none(),
           R"(Sets the velocity [m/s] and/or angular velocity [rad/s, world frame] of the free
particle `uid` between steps (collective: the same call on every rank). They are the leapfrog's
values at time - dt/2, as particles() reports them; checkpoints keep the change. ValueError if no
free particle has that uid, or for a value that is not finite or would move a point of the
particle more than `step_reach` in one step (|v| dt, or |w| r dt with r its circumradius).)")
      .def_static("restart", &restart, py::arg("path"), py::arg("comm") = py::none(),
                  py::arg("operators") = py::none(), py::keep_alive<0, 2>(),
                  R"(Continues the run stored in the checkpoint `path` (collective) on `comm`
(None: MPI_COMM_WORLD; or an mpi4py communicator), on any number of ranks. Stepping it on gives
the same bits as the run that wrote it would have. `operators`: as for Simulation(), the
functions of the scene's [[operator]]s that name no library (operators added in code with
add_force_operator are not stored: add them again). Raises polydem.CheckpointError for a missing,
corrupted or mismatching file.)");
}

}  // namespace polydem::python

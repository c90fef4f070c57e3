// Shared pieces of the _polydem extension: numpy conversions of the core types and the functions
// that add each area's bindings to the module (one file per area: geometry, contact, scene,
// simulation; module.cpp ties them together and owns MPI and the exception classes).
//
// Conventions of the Python API: coordinates and vectors are float64 numpy arrays, lists of points
// are (n, 3), matrices (3, 3), quaternions (4,) as (w, x, y, z); every quantity is in SI units.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "polydem/core/types.h"
#include "polydem/geometry/rock_mass.h"
#include "polydem/sim/simulation.h"

namespace polydem::python {

namespace py = pybind11;

/// (n, 3) points from anything numpy can read as such (array, list of triples). Throws
/// py::value_error naming `what` for any other shape or for non-numeric entries.
std::vector<Vec3> toPoints(const py::handle& object, const char* what);
/// A 3-vector from any array-like of 3 numbers; py::value_error naming `what` otherwise.
Vec3 toVec3(const py::handle& object, const char* what);
/// A 3 x 3 matrix from any (3, 3) array-like; py::value_error naming `what` otherwise.
Mat3 toMat3(const py::handle& object, const char* what);

py::array_t<double> pointsArray(std::span<const Vec3> points);
py::array_t<double> vec3Array(const Vec3& v);
py::array_t<double> mat3Array(const Mat3& m);
py::array_t<double> quatArray(const Quat& q);  // (w, x, y, z)

/// An empty C-contiguous numpy array of the given shape, to be filled through data().
template <typename T>
py::array_t<T> emptyArray(std::vector<py::ssize_t> shape) {
  return py::array_t<T>(std::move(shape));
}

/// A member function bound through a reference to self. pybind11 passes None as a null pointer to
/// a member function bound directly (&C::f), so Simulation.time.fget(None) would call it on null
/// and crash the interpreter; through a reference, None raises TypeError.
template <typename C, typename R, typename... A>
auto method(R (C::*f)(A...) const) {
  return [f](const C& self, A... args) -> R { return (self.*f)(std::forward<A>(args)...); };
}
template <typename C, typename R, typename... A>
auto method(R (C::*f)(A...)) {
  return [f](C& self, A... args) -> R { return (self.*f)(std::forward<A>(args)...); };
}

/// Raises KeyboardInterrupt (through py::error_already_set) if Ctrl-C was pressed; called between
/// steps of long runs, which hold the GIL.
void checkSignals();

/// The communicator of a `comm` argument: None is MPI_COMM_WORLD, else an mpi4py communicator
/// (through its py2f()). TypeError for anything else, ValueError for COMM_NULL.
MPI_Comm toComm(const py::object& comm);
/// The simulation of a SceneData, a polydem.Scene (through its build()) or a scene file's path,
/// on `comm`, with `operators` (None or a dict {name: fn}) for the scene's [[operator]]s that
/// name no library (sim/scene_operators.h).
std::unique_ptr<sim::Simulation> makeSimulation(const py::object& scene, const py::object& comm,
                                                const py::object& operators);
/// A Python function fn(time, dt, particles) -> forces as a force operator named `name`
/// (TypeError if it is not callable).
sim::ForceOperator pythonForceOperator(const std::string& name, py::object fn);
/// A dict {name: fn} (or None) as the operators a program supplies to a scene.
sim::HostOperators pythonOperators(const py::object& operators);
/// write_checkpoint and restart (sim/restart.cpp).
void bindSimulationCheckpoint(py::class_<sim::Simulation>& c);

void bindGeometry(py::module_& m);
void bindContact(py::module_& m);
void bindScene(py::module_& m);
void bindSimulation(py::module_& m);
void bindRockMass(py::module_& m);
/// A rock mass's report (counts and volumes) as a dict.
py::dict rockMassReport(const geometry::RockMassReport& r);

}  // namespace polydem::python

// The _polydem extension module: MPI for the lifetime of the interpreter, polydem's errors as
// Python exceptions, logging, numpy conversions, and the bindings of each area.
//
// MPI: importing the module initialises MPI (MPI_THREAD_SERIALIZED: the GIL, which every call
// into polydem holds, serialises MPI calls from Python threads) unless something else, e.g.
// mpi4py, already did; then it finalises it when the interpreter ends. The finalisation is
// registered with Py_AtExit, which runs after the last Python object (a Simulation a script left
// in a global) is destroyed, so no destructor ever runs after MPI_Finalize.
#include <Python.h>

#include <string>

#include "bindings.h"
#include "polydem/checkpoint/checkpoint.h"
#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"
#include "polydem/hdf5/library.h"

namespace polydem::python {

namespace {

// Exception classes, created once at import and kept for the life of the process (a py::object
// would be released at interpreter shutdown, after which a translator could still run).
PyObject* g_error = nullptr;
PyObject* g_input_error = nullptr;
PyObject* g_geometry_error = nullptr;
PyObject* g_checkpoint_error = nullptr;
PyObject* g_simulation_error = nullptr;

PyObject* newException(py::module_& m, const char* name, const char* doc, py::tuple bases) {
  const std::string qualified = std::string("polydem.") + name;
  PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), /*dict=*/nullptr);
  if (type == nullptr) throw py::error_already_set();
  m.add_object(name, py::handle(type));
  return type;
}

void defineExceptions(py::module_& m) {
  const py::handle runtime(PyExc_RuntimeError), value(PyExc_ValueError);
  g_error = newException(m, "Error", "Base class of every error polydem raises.",
                         py::make_tuple(runtime));
  const py::handle base(g_error);
  g_input_error = newException(
      m, "InputError",
      "A problem in an input file (scene): the message starts with 'file:line: ', and the\n"
      "attributes `file` and `line` hold them.",
      py::make_tuple(base, value));
  g_geometry_error = newException(
      m, "GeometryError",
      "A shape that is not a proper convex polyhedron (too few points, flat, NaN, duplicates).",
      py::make_tuple(base, value));
  g_checkpoint_error =
      newException(m, "CheckpointError", "An unreadable, corrupted or mismatched checkpoint.",
                   py::make_tuple(base));
  g_simulation_error = newException(
      m, "SimulationError", "A physical state that cannot go on (NaN force, particle lost).",
      py::make_tuple(base));

  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      // An instance carrying file and line, so that scripts need not parse the message.
      py::object error = py::reinterpret_borrow<py::object>(g_input_error)(e.what());
      error.attr("file") = e.file();
      error.attr("line") = e.line();
      PyErr_SetObject(g_input_error, error.ptr());
    } catch (const GeometryError& e) {
      PyErr_SetString(g_geometry_error, e.what());
    } catch (const CheckpointError& e) {
      PyErr_SetString(g_checkpoint_error, e.what());
    } catch (const SimulationError& e) {
      PyErr_SetString(g_simulation_error, e.what());
    } catch (const Error& e) {
      PyErr_SetString(g_error, e.what());
    }
  });
}

void finalizeMpi() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (finalized) return;
  hdf5::closeHdf5Library();  // quietly, before MPI_Finalize would close it
                             // (checkpoint/checkpoint.h)
  MPI_Finalize();
}

void initializeMpi() {
  int initialized = 0, finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  if (finalized) throw py::import_error("polydem: MPI has already been finalised in this process");
  if (!initialized) {
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided);
    if (Py_AtExit(finalizeMpi) != 0) {
      throw py::import_error("polydem: cannot register MPI_Finalize with Py_AtExit");
    }
  }
  log::setRank(mpi::rank());
}

log::Level levelByName(const std::string& name) {
  if (name == "quiet") return log::Level::kQuiet;
  if (name == "warning") return log::Level::kWarning;
  if (name == "info") return log::Level::kInfo;
  if (name == "detail") return log::Level::kDetail;
  throw py::value_error(cat("unknown log level '", name, "'; known: quiet, warning, info, detail"));
}

const char* levelName(log::Level level) {
  switch (level) {
    case log::Level::kQuiet:
      return "quiet";
    case log::Level::kWarning:
      return "warning";
    case log::Level::kInfo:
      return "info";
    case log::Level::kDetail:
      return "detail";
  }
  return "info";
}

using ArrayIn = py::array_t<double, py::array::c_style | py::array::forcecast>;

std::string shapeText(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += cat(i ? ", " : "", a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

// The object as a float64 array, or a ValueError naming `what`.
ArrayIn toArray(const py::handle& object, const char* what, const char* expected) {
  ArrayIn a = ArrayIn::ensure(object);
  if (!a) {
    PyErr_Clear();
    throw py::value_error(cat(what, " must be ", expected, " of numbers"));
  }
  return a;
}

}  // namespace

std::vector<Vec3> toPoints(const py::handle& object, const char* what) {
  const ArrayIn a = toArray(object, what, "an (n, 3) array");
  if (a.ndim() != 2 || a.shape(1) != 3) {
    throw py::value_error(
        cat(what, " must be an (n, 3) array of coordinates, got shape ", shapeText(a)));
  }
  std::vector<Vec3> points(static_cast<std::size_t>(a.shape(0)));
  const double* d = a.data();
  for (std::size_t i = 0; i < points.size(); ++i)
    points[i] = {d[3 * i], d[3 * i + 1], d[3 * i + 2]};
  return points;
}

Vec3 toVec3(const py::handle& object, const char* what) {
  const ArrayIn a = toArray(object, what, "a 3-vector");
  if (a.ndim() != 1 || a.shape(0) != 3) {
    throw py::value_error(cat(what, " must be a 3-vector, got shape ", shapeText(a)));
  }
  return {a.data()[0], a.data()[1], a.data()[2]};
}

Mat3 toMat3(const py::handle& object, const char* what) {
  const ArrayIn a = toArray(object, what, "a (3, 3) array");
  if (a.ndim() != 2 || a.shape(0) != 3 || a.shape(1) != 3) {
    throw py::value_error(cat(what, " must be a (3, 3) matrix, got shape ", shapeText(a)));
  }
  Mat3 m;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m(r, c) = a.data()[3 * r + c];
  }
  return m;
}

py::array_t<double> pointsArray(std::span<const Vec3> points) {
  auto a = emptyArray<double>({static_cast<py::ssize_t>(points.size()), 3});
  double* d = a.mutable_data();
  for (const Vec3& p : points) {
    *d++ = p.x();
    *d++ = p.y();
    *d++ = p.z();
  }
  return a;
}

py::array_t<double> vec3Array(const Vec3& v) {
  auto a = emptyArray<double>({3});
  for (int i = 0; i < 3; ++i) a.mutable_data()[i] = v[i];
  return a;
}

py::array_t<double> mat3Array(const Mat3& m) {
  auto a = emptyArray<double>({3, 3});
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) a.mutable_data()[3 * r + c] = m(r, c);
  }
  return a;
}

py::array_t<double> quatArray(const Quat& q) {
  auto a = emptyArray<double>({4});
  double* d = a.mutable_data();
  d[0] = q.w();
  d[1] = q.x();
  d[2] = q.y();
  d[3] = q.z();
  return a;
}

void checkSignals() {
  if (PyErr_CheckSignals() != 0) throw py::error_already_set();
}

}  // namespace polydem::python

PYBIND11_MODULE(_polydem, m) {
  namespace py = pybind11;
  using namespace polydem;
  using namespace polydem::python;
  m.doc() = "polydem's C++ core (use the package `polydem`, which re-exports it)";
  m.attr("__version__") = POLYDEM_VERSION;

  initializeMpi();
  defineExceptions(m);

  m.def(
      "mpi_rank", [] { return mpi::rank(); }, "This process's rank in MPI_COMM_WORLD.");
  m.def(
      "mpi_size", [] { return mpi::size(); }, "The number of ranks in MPI_COMM_WORLD.");
  m.def(
      "mpi_abort", [](int code) { MPI_Abort(MPI_COMM_WORLD, code); }, py::arg("code") = 1,
      "Ends every rank of the job at once (after an error on one rank, the others may be\n"
      "waiting in a collective call and would never return).");
  m.def(
      "set_log_level", [](const std::string& level) { log::setLevel(levelByName(level)); },
      py::arg("level"),
      "How much polydem prints (rank 0 only): 'quiet', 'warning', 'info' (default), 'detail'.");
  m.def(
      "log_level", [] { return levelName(log::level()); }, "The current log level.");

  bindGeometry(m);
  bindContact(m);
  bindScene(m);
  bindSimulation(m);
  bindRockMass(m);
}

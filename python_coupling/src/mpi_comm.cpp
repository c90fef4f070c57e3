// The communicator a Python caller passes: None (MPI_COMM_WORLD) or an mpi4py communicator. The
// handle is taken through mpi4py's public py2f() (a Fortran integer, turned back with
// MPI_Comm_f2c), so the extension needs neither mpi4py's headers nor mpi4py itself to build.
#include <mpi.h>

#include <string>

#include "bindings.h"
#include "polydem/core/strings.h"

namespace polydem::python {

MPI_Comm toComm(const py::object& comm) {
  if (comm.is_none()) return MPI_COMM_WORLD;
  if (!py::hasattr(comm, "py2f")) {
    throw py::type_error(cat("comm must be None (MPI_COMM_WORLD) or an mpi4py communicator, got ",
                             py::str(py::type::of(comm).attr("__name__")).cast<std::string>()));
  }
  const py::object handle = comm.attr("py2f")();
  if (!py::isinstance<py::int_>(handle)) {
    throw py::type_error("comm.py2f() did not return an integer: not an mpi4py communicator");
  }
  const MPI_Comm c = MPI_Comm_f2c(static_cast<MPI_Fint>(handle.cast<long long>()));
  if (c == MPI_COMM_NULL) throw py::value_error("comm is MPI.COMM_NULL");
  int inter = 0;
  MPI_Comm_test_inter(c, &inter);
  if (inter)
    throw py::value_error("comm is an intercommunicator; polydem needs an intracommunicator");
  return c;
}

}  // namespace polydem::python

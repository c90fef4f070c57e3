// polydem_bench_checkpoint: runs the checkpoint benchmark (bench_checkpoint.cpp) on its own, with
// the options of `polydem bench checkpoint`, e.g. mpirun -n 2 polydem_bench_checkpoint --json f.
#include <exception>

#include "commands.h"
#include "polydem/checkpoint/checkpoint.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/hdf5/library.h"

int main(int argc, char** argv) {
  polydem::mpi::Environment env(argc, argv);
  try {
    const int status = polydem::app::benchCheckpoint(argc - 1, argv + 1);
    polydem::hdf5::closeHdf5Library();
    return status;
  } catch (const polydem::app::UsageError& e) {
    polydem::log::error(e.what());
    return 2;
  } catch (const std::exception& e) {
    polydem::log::error(e.what());
    MPI_Abort(MPI_COMM_WORLD, 1);
    return 1;
  }
}

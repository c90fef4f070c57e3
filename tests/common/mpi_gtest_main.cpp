// GoogleTest main for every polydem test: initialises MPI, runs the tests on all ranks, prints
// results from rank 0 only, and fails the process if a test failed on any rank.
#include <gtest/gtest.h>
#include <mpi.h>

#include "polydem/core/mpi_env.h"

int main(int argc, char** argv) {
  polydem::mpi::Environment env(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  // On several ranks an exception on one rank would leave the others waiting in a collective
  // forever; letting it escape ends this process, and mpiexec then ends the whole job at once.
  if (polydem::mpi::size() > 1) ::testing::GTEST_FLAG(catch_exceptions) = false;
  if (polydem::mpi::rank() != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  const int local = RUN_ALL_TESTS();
  int global = 0;
  MPI_Allreduce(&local, &global, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return global;
}

// MPI set-up and the few collective helpers every module uses.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <vector>

namespace polydem::mpi {

/// Initialises MPI for the lifetime of the object (once per process) and tells the logger the
/// rank. Safe to construct when MPI is already initialised (then it does not finalise).
class Environment {
 public:
  Environment(int& argc, char**& argv);
  ~Environment();
  Environment(const Environment&) = delete;
  Environment& operator=(const Environment&) = delete;

 private:
  bool owns_ = false;
};

int rank(MPI_Comm comm = MPI_COMM_WORLD);
int size(MPI_Comm comm = MPI_COMM_WORLD);

double allreduceMax(double value, MPI_Comm comm = MPI_COMM_WORLD);
double allreduceMin(double value, MPI_Comm comm = MPI_COMM_WORLD);
std::int64_t allreduceSum(std::int64_t value, MPI_Comm comm = MPI_COMM_WORLD);
bool allreduceOr(bool value, MPI_Comm comm = MPI_COMM_WORLD);

/// Gathers a variable number of plain values from every rank to all ranks, in rank order.
template <typename T>
std::vector<T> allgatherv(const std::vector<T>& local, MPI_Comm comm = MPI_COMM_WORLD) {
  const int n = size(comm);
  const int my_bytes = static_cast<int>(local.size() * sizeof(T));
  std::vector<int> bytes(n), displs(n);
  MPI_Allgather(&my_bytes, 1, MPI_INT, bytes.data(), 1, MPI_INT, comm);
  int total = 0;
  for (int r = 0; r < n; ++r) {
    displs[r] = total;
    total += bytes[r];
  }
  std::vector<T> all(static_cast<std::size_t>(total) / sizeof(T));
  MPI_Allgatherv(local.data(), my_bytes, MPI_BYTE, all.data(), bytes.data(), displs.data(),
                 MPI_BYTE, comm);
  return all;
}

/// Gathers to `root` only; other ranks get an empty vector.
template <typename T>
std::vector<T> gatherv(const std::vector<T>& local, int root = 0, MPI_Comm comm = MPI_COMM_WORLD) {
  const int n = size(comm);
  const int my_bytes = static_cast<int>(local.size() * sizeof(T));
  std::vector<int> bytes(n), displs(n);
  MPI_Gather(&my_bytes, 1, MPI_INT, bytes.data(), 1, MPI_INT, root, comm);
  int total = 0;
  for (int r = 0; r < n; ++r) {
    displs[r] = total;
    total += bytes[r];
  }
  std::vector<T> all;
  if (rank(comm) == root) all.resize(static_cast<std::size_t>(total) / sizeof(T));
  MPI_Gatherv(local.data(), my_bytes, MPI_BYTE, all.data(), bytes.data(), displs.data(), MPI_BYTE,
              root, comm);
  return all;
}

}  // namespace polydem::mpi

// Helpers shared by the output-writer tests: scratch directories and a few closed polyhedra with
// outward, counter-clockwise faces.
#pragma once

#include <mpi.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "polydem/core/types.h"

namespace polydem::output::test {

/// A fresh, empty directory shared by the ranks of `comm` (rank 0 names and creates it), removed
/// again when the test ends.
class ScratchDir {
 public:
  ScratchDir(const std::string& name, MPI_Comm comm) : comm_(comm) {
    MPI_Comm_rank(comm_, &rank_);
    char path[512] = {};
    if (rank_ == 0) {
      const auto dir = std::filesystem::temp_directory_path() /
                       ("polydem_io_" + name + "_" + std::to_string(::getpid()));
      std::filesystem::remove_all(dir);
      std::filesystem::create_directories(dir);
      std::snprintf(path, sizeof path, "%s", dir.c_str());
    }
    MPI_Bcast(path, sizeof path, MPI_CHAR, 0, comm_);
    path_ = path;
  }
  ~ScratchDir() {
    MPI_Barrier(comm_);
    std::error_code ignored;
    if (rank_ == 0) std::filesystem::remove_all(path_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::string& path() const { return path_; }

 private:
  MPI_Comm comm_;
  int rank_ = 0;
  std::string path_;
};

struct Mesh {
  std::vector<Vec3> vertices;
  std::vector<std::vector<int>> faces;
};

/// Axis-aligned box [lo, lo + size]; vertex i has bit 0 = x, bit 1 = y, bit 2 = z.
inline Mesh box(const Vec3& lo, const Vec3& size) {
  Mesh m;
  for (int i = 0; i < 8; ++i) {
    m.vertices.push_back(
        lo + Vec3((i & 1) ? size.x() : 0, (i & 2) ? size.y() : 0, (i & 4) ? size.z() : 0));
  }
  m.faces = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  return m;
}

/// Corner tetrahedron lo + {0, s e_x, s e_y, s e_z}.
inline Mesh tetrahedron(const Vec3& lo, double s) {
  Mesh m;
  m.vertices = {lo, lo + Vec3(s, 0, 0), lo + Vec3(0, s, 0), lo + Vec3(0, 0, s)};
  m.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return m;
}

/// Regular hexagonal prism: circumradius r, axis z from `base` up by h (two hexagons, six quads).
inline Mesh hexagonalPrism(const Vec3& base, double r, double h) {
  Mesh m;
  for (int level = 0; level < 2; ++level) {
    for (int k = 0; k < 6; ++k) {
      const double a = kPi / 3 * k;
      m.vertices.push_back(base + Vec3(r * std::cos(a), r * std::sin(a), level * h));
    }
  }
  m.faces = {{5, 4, 3, 2, 1, 0}, {6, 7, 8, 9, 10, 11}};
  for (int k = 0; k < 6; ++k) m.faces.push_back({k, (k + 1) % 6, 6 + (k + 1) % 6, 6 + k});
  return m;
}

}  // namespace polydem::output::test

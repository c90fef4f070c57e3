// polydem bench kernels | scaling | memory | checkpoint | yade | lammps | peers: the benchmarks of
// the README.
#include <cstdio>
#include <string>

#include "commands.h"

namespace polydem::app {

int benchCheckpoint(int argc, char** argv);
#ifdef POLYDEM_WITH_BENCHMARKS
int benchContactModel(int argc, char** argv);
int benchKernels(int argc, char** argv);
int benchMemory(int argc, char** argv);
int benchScaling(int argc, char** argv);
int benchYade(int argc, char** argv);
int benchLammps(int argc, char** argv);
int benchPeers(int argc, char** argv);
#endif

int benchCommand(int argc, char** argv) {
  const std::string which = argc > 0 ? argv[0] : "";
  if (which == "checkpoint") return benchCheckpoint(argc - 1, argv + 1);
#ifdef POLYDEM_WITH_BENCHMARKS
  if (which == "kernels") return benchKernels(argc - 1, argv + 1);
  if (which == "scaling") return benchScaling(argc - 1, argv + 1);
  if (which == "memory") return benchMemory(argc - 1, argv + 1);
  if (which == "contact-model") return benchContactModel(argc - 1, argv + 1);
  if (which == "yade") return benchYade(argc - 1, argv + 1);
  if (which == "lammps") return benchLammps(argc - 1, argv + 1);
  if (which == "peers") return benchPeers(argc - 1, argv + 1);
  std::printf(
      "usage: polydem bench kernels [--help]   contact kernels vs libccd (P-KERNELS)\n"
      "       mpirun -n P polydem bench scaling [--help]   strong scaling of P-PILE\n"
      "       mpirun -n P polydem bench memory [--help]   heap per particle by structure\n"
      "       polydem bench contact-model [--help]   sub-contacts vs the point model\n"
      "       mpirun -n P polydem bench checkpoint [--help]   checkpoint bandwidth vs raw HDF5\n"
      "       polydem bench yade [--help]   polydem beside Yade on settled turned cubes\n"
      "       polydem bench lammps [--help]   polydem beside LAMMPS's BODY package, same pile\n"
      "       polydem bench peers [--help]   polydem, Yade and LAMMPS on one settled pile\n");
  return which == "--help" ? 0 : 2;
#else
  std::fprintf(stderr, "polydem was built without benchmarks (POLYDEM_BUILD_BENCHMARKS=OFF)\n");
  return 2;
#endif
}

}  // namespace polydem::app

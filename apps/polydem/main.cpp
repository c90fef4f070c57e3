// polydem: the command-line entry point. Each sub-command lives in its own file (cmd_*.cpp).
#include <malloc.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <string>

#include "commands.h"
#include "polydem/checkpoint/checkpoint.h"
#include "polydem/core/error.h"
#include "polydem/core/logging.h"
#include "polydem/core/mpi_env.h"
#include "polydem/hdf5/library.h"
#include "polydem/output/output_file.h"
#include "polydem/run/run_checkpoint.h"

namespace polydem::app {

std::string programPath() {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return "polydem";
  // A program rebuilt while it runs reads as "PATH (deleted)": the command to print is PATH.
  std::string path = exe.string();
  const std::string deleted = " (deleted)";
  if (path.ends_with(deleted)) path.resize(path.size() - deleted.size());
  return path;
}

}  // namespace polydem::app

namespace {

void usage() {
  std::printf(
      "polydem %s: polyhedral DEM for rock-slope failure and runout\n\n"
      "usage: polydem <command> [options]\n\n"
      "commands:\n"
      "  run SCENE --out DIR      run a scene file (mpirun -n N polydem run ... for N ranks)\n"
      "  run --restart FILE --out DIR   continue a run from a checkpoint (any rank count)\n"
      "  fos SCENE --out DIR      factor of safety by strength reduction (trials side by side\n"
      "                           over the ranks)\n"
      "  runout SCENE --out DIR   run a scene until at rest: runout distance, deposit and its\n"
      "                           thickness map\n"
      "  checkpoint info FILE     verify a checkpoint and print its summary\n"
      "  contact --kernel NAME    resolve contacts of vertex lists given as JSON lines\n"
      "  report contact-types     the contact-type table of every kernel (BENCHMARKS.md C)\n"
      "  bench kernels|scaling    benchmarks (see README)\n"
      "  kernels                  list the contact kernels\n"
      "  version                  print the version\n\n"
      "Run 'polydem <command> --help' for a command's options.\n",
      polydem::app::version());
}

// Runs the command named by argv[1]; its exit status.
int dispatch(int argc, char** argv) {
  if (argc < 2 || std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0) {
    usage();
    return argc < 2 ? 2 : 0;
  }
  const std::string command = argv[1];
  const int sub_argc = argc - 2;
  char** sub_argv = argv + 2;
  try {
    if (command == "run") return polydem::app::runCommand(sub_argc, sub_argv);
    if (command == "fos") return polydem::app::fosCommand(sub_argc, sub_argv);
    if (command == "runout") return polydem::app::runoutCommand(sub_argc, sub_argv);
    if (command == "contact") return polydem::app::contactCommand(sub_argc, sub_argv);
    if (command == "checkpoint") return polydem::app::checkpointCommand(sub_argc, sub_argv);
    if (command == "report") return polydem::app::reportCommand(sub_argc, sub_argv);
    if (command == "bench") return polydem::app::benchCommand(sub_argc, sub_argv);
    if (command == "kernels") return polydem::app::kernelsCommand(sub_argc, sub_argv);
    if (command == "version") {
      std::printf("polydem %s\n", polydem::app::version());
      return 0;
    }
    polydem::log::error("unknown command '" + command + "' (polydem --help lists them)");
    return 2;
  } catch (const polydem::app::UsageError& e) {
    if (polydem::mpi::rank() == 0) polydem::log::error(e.what());
    return 2;
  } catch (const polydem::InputError& e) {
    // Every rank reads the same input and stops at the same error: finish MPI normally.
    if (polydem::mpi::rank() == 0) polydem::log::error(e.what());
    return 1;
  } catch (const polydem::CheckpointError& e) {
    // Checkpoints are read, verified and written collectively: every rank throws the same error.
    if (polydem::mpi::rank() == 0) polydem::log::error(e.what());
    return 1;
  } catch (const polydem::OutputError& e) {
    // Agreed among the ranks (a busy output folder, a full disk): every rank throws the same error.
    if (polydem::mpi::rank() == 0) polydem::log::error(e.what());
    return 1;
  } catch (const std::exception& e) {
    // An error that may be local to this rank: the others may be waiting in a collective.
    polydem::log::error(e.what());
    if (polydem::mpi::size() > 1) MPI_Abort(MPI_COMM_WORLD, 1);
    return 1;
  }
}

// For scripts/polydem-mpirun: rank 0 writes "polydem exit status N" to $POLYDEM_STATUS_FILE once
// the command has returned on every rank that got this far, so that the wrapper can tell a clean
// stop from a failure even when mpirun itself exits 1 because it was signalled.
void reportStatus(int status) {
  const char* file = std::getenv("POLYDEM_STATUS_FILE");
  if (file == nullptr || *file == '\0' || polydem::mpi::rank() != 0) return;
  if (std::FILE* f = std::fopen(file, "w")) {
    std::fprintf(f, "polydem exit status %d\n", status);
    std::fclose(f);
  }
}

}  // namespace

int main(int argc, char** argv) {
  // Tables of a million blocks grow step by step in the first steps (contact history, records):
  // glibc's default moves its mmap threshold up to each freed block (up to 32 MB), so the
  // outgrown copies below that stay in the heap as holes that nothing refills, a hundred MB at
  // a few thousand blocks. A fixed threshold maps every block above 4 MB on its own and returns
  // it when freed. A warm step allocates nothing, so this costs no step time.
  mallopt(M_MMAP_THRESHOLD, 4 << 20);
  // `run` and `runout` turn SIGTERM and SIGUSR1 into a checkpoint at the end of the step, `fos`
  // these and SIGINT into fos.json with the trials so far. The handlers go in before MPI starts and
  // before any file is read, so that no moment of the start-up is left in which a signal would end
  // the job with nothing written.
  if (argc >= 2 && std::strcmp(argv[1], "run") == 0) polydem::run::installStopSignals();
  if (argc >= 2 && std::strcmp(argv[1], "runout") == 0) polydem::run::installStopSignals();
  if (argc >= 2 && std::strcmp(argv[1], "fos") == 0) polydem::run::installStopSignals(true);
  polydem::mpi::Environment env(argc, argv);
  const int status = dispatch(argc, argv);
  reportStatus(status);
  polydem::hdf5::closeHdf5Library();  // before MPI_Finalize (env's destructor), without noise
  return status;
}

// polydem checkpoint info FILE: verifies every dataset of a checkpoint (collective, any rank
// count) and prints its summary.
#include <cstdio>

#include "commands.h"
#include "polydem/checkpoint/checkpoint.h"
#include "polydem/core/mpi_env.h"

namespace polydem::app {

int checkpointCommand(int argc, char** argv) {
  Args args(argc, argv, {"help"});
  const auto& words = args.positional();
  if (args.flag("help") || words.size() != 2 || words[0] != "info") {
    std::printf(
        "usage: [mpirun -n N] polydem checkpoint info FILE.h5\n"
        "  verifies every dataset's checksum, shape and type, and prints what the file holds\n"
        "  (step, time, stage, counts, kinetic energy, datasets with their checksums).\n"
        "  Exit status 0 if the file is intact, 1 with the problem otherwise.\n");
    return args.flag("help") ? 0 : 2;
  }
  args.rejectUnknown();
  const checkpoint::CheckpointSummary summary =
      checkpoint::verifyCheckpoint(words[1], MPI_COMM_WORLD);
  if (mpi::rank() == 0) std::printf("%s", checkpoint::formatCheckpointSummary(summary).c_str());
  return 0;
}

}  // namespace polydem::app

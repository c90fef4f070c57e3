// Writes everything a checkpoint holds into an open file (internal to checkpoint; writeCheckpoint
// in checkpoint_write.cpp handles validation, the temporary file and the rename). Collective.
#pragma once

#include "polydem/checkpoint/checkpoint.h"
#include "polydem/hdf5/hdf5_file.h"

namespace polydem::checkpoint {

void writeContents(hdf5::File& file, const sim::CheckpointData& data);

}  // namespace polydem::checkpoint

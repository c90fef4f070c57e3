// readCheckpoint with the list of verified datasets, for verifyCheckpoint (internal to io/).
#pragma once

#include <filesystem>
#include <vector>

#include "io/checkpoint.h"

namespace polydem::io {

CheckpointData readCheckpointVerified(const std::filesystem::path& path, MPI_Comm comm,
                                      const CheckpointIoOptions& options,
                                      std::vector<CheckpointDatasetInfo>* datasets);

}  // namespace polydem::io

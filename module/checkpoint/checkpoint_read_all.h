// readCheckpoint with the list of verified datasets, for verifyCheckpoint, and the check of step
// and time the writer and the reader share (internal to checkpoint).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "polydem/checkpoint/checkpoint.h"

namespace polydem::checkpoint {

/// The loop of a stage adds dt once per step to an exact sum (timeloop/time_loop.h), so a
/// checkpoint's time is exactly step x dt, and in the equilibrium stage its step is the
/// equilibrium step count: what is wrong with `d` in these respects, or nothing. The writer
/// refuses such data, the reader such files.
std::optional<std::string> stepTimeProblem(const sim::CheckpointData& d);

sim::CheckpointData readCheckpointVerified(const std::filesystem::path& path, MPI_Comm comm,
                                           const hdf5::CheckpointIoOptions& options,
                                           std::vector<hdf5::CheckpointDatasetInfo>* datasets);

}  // namespace polydem::checkpoint

// Pair histories handed to a restart in bounded chunks (Simulation's restoring constructor), so
// that a rank never holds its whole share of a checkpoint's histories in transit form: the
// checkpoint module reads them from the file round by round (checkpoint/checkpoint.h
// CheckpointReader); SavedHistoryChunks hands out those of a CheckpointData held in memory.
#pragma once

#include <mpi.h>

#include <cstddef>

#include "polydem/particles/contact_history.h"
#include "polydem/sim/saved_state.h"

namespace polydem::sim {

class HistoryChunks {
 public:
  virtual ~HistoryChunks() = default;
  /// Collective: replaces `chunk` by the next chunk of this rank's share (possibly empty) and
  /// returns true, or returns false on every rank at once when no rank has any left. Every pair
  /// history comes before the sub-contact histories of any pair, so that a merged sub-contact
  /// finds its pair.
  virtual bool next(particles::HistoryRecords& chunk) = 0;
};

/// The histories of `data` (this rank's share), at most `records` per chunk: the pairs first,
/// then the sub-contacts (or, from a history_view, pairs with their sub-contacts). Collective
/// construction (the ranks agree on the chunk counts).
class SavedHistoryChunks final : public HistoryChunks {
 public:
  SavedHistoryChunks(const CheckpointData& data, MPI_Comm comm,
                     std::size_t records = std::size_t{1} << 18);
  bool next(particles::HistoryRecords& chunk) override;

 private:
  const CheckpointData& data_;
  std::size_t records_;
  std::size_t pair_chunks_ = 0, sub_chunks_ = 0, next_ = 0;
};

}  // namespace polydem::sim

// Sparse personalised exchange: every rank sends one byte buffer to each of a few other ranks and
// receives what the others sent it. Used for migration and ghost refresh.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <map>
#include <vector>

#include "polydem/core/byte_buffer.h"

namespace polydem::comm {

struct Message {
  int rank = -1;  // source
  std::vector<std::byte> bytes;
};

/// What one exchange cost this rank. The time splits into the agreement on the message sizes,
/// a collective that every rank enters only when its own step's work is done, so that it
/// measures mostly the wait for the slowest rank, and the transfer of the messages proper.
struct ExchangeCost {
  std::int64_t bytes = 0;     // sent
  std::int64_t messages = 0;  // sent (one per destination rank)
  double wait_seconds = 0.0;
  double transfer_seconds = 0.0;
};

/// Sends outgoing[r] to rank r (empty buffers are not sent) and returns the messages received,
/// sorted by source rank so that unpacking order never depends on arrival order. Collective.
/// Message sizes are first exchanged with MPI_Alltoall (one 64-bit count per rank pair): simple
/// and robust up to thousands of ranks. Adds what it cost to `cost` if given.
std::vector<Message> sparseExchange(const std::map<int, SendBuffer>& outgoing, MPI_Comm comm,
                                    int tag, ExchangeCost* cost = nullptr);

}  // namespace polydem::comm

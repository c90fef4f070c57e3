// Sparse personalised exchange: every rank sends one byte buffer to each of a few other ranks and
// receives what the others sent it. Used for migration and ghost refresh.
#pragma once

#include <mpi.h>

#include <map>
#include <vector>

#include "core/byte_buffer.h"

namespace polydem::comm {

struct Message {
  int rank = -1;  // source
  std::vector<std::byte> bytes;
};

/// Sends outgoing[r] to rank r (empty buffers are not sent) and returns the messages received,
/// sorted by source rank so that unpacking order never depends on arrival order. Collective.
/// Message sizes are first exchanged with MPI_Alltoall (one 64-bit count per rank pair): simple
/// and robust up to thousands of ranks. Returns the bytes this rank sent in `bytes_sent`.
std::vector<Message> sparseExchange(const std::map<int, SendBuffer>& outgoing, MPI_Comm comm,
                                    int tag, std::int64_t* bytes_sent = nullptr);

}  // namespace polydem::comm

// Sparse personalised exchange: every rank sends one byte buffer to each of a few other ranks and
// receives what the others sent it. sparseExchange works for any destinations and agrees on the
// message sizes with a collective (O(ranks) per rank); neighbourExchange, for the step's exchange,
// only talks to a fixed symmetric set of neighbour ranks (O(neighbours) per rank).
#pragma once

#include <mpi.h>

#include <cstdint>
#include <map>
#include <span>
#include <vector>

#include "polydem/core/byte_buffer.h"

namespace polydem::comm {

struct Message {
  int rank = -1;  // source
  std::vector<std::byte> bytes;
};

/// What one exchange cost this rank. The time splits into the wait, until the message sizes are
/// known (sparseExchange: the collective that agrees on them, which every rank enters only when
/// its own step's work is done; neighbourExchange: until every neighbour's message has arrived,
/// i.e. the neighbours have finished their step), and the transfer of the messages proper.
struct ExchangeCost {
  std::int64_t bytes = 0;     // sent
  std::int64_t messages = 0;  // sent (one per destination rank; neighbourExchange: including
                              // the empty ones, which the neighbours wait for)
  double wait_seconds = 0.0;
  double transfer_seconds = 0.0;
};

/// Sends outgoing[r] to rank r (empty buffers are not sent) and returns the messages received,
/// sorted by source rank so that unpacking order never depends on arrival order. Collective.
/// Message sizes are first exchanged with MPI_Alltoall (one 64-bit count per rank pair): simple
/// and robust up to thousands of ranks. Adds what it cost to `cost` if given.
std::vector<Message> sparseExchange(const std::map<int, SendBuffer>& outgoing, MPI_Comm comm,
                                    int tag, ExchangeCost* cost = nullptr);

/// Sends outgoing[r] to every rank r in `neighbours` (sorted, without this rank), as an empty
/// message where there is nothing, and receives one message from each of them; returns the
/// non-empty ones sorted by source rank. No collective: each message brings its own size
/// (MPI_Mprobe), so a rank waits only for its neighbours. The neighbour relation must be
/// symmetric (every rank expects exactly one message from each of its neighbours). Throws Error,
/// before sending anything, if `outgoing` holds a buffer for a rank that is not a neighbour.
std::vector<Message> neighbourExchange(const std::map<int, SendBuffer>& outgoing,
                                       std::span<const int> neighbours, MPI_Comm comm, int tag,
                                       ExchangeCost* cost = nullptr);

/// The sends of a neighbour exchange in flight: posted by postNeighbourSends, completed by
/// receiveNeighbourMessages (the buffers given to the first must live until then). Work done in
/// between overlaps the transfer (neighbourExchange is the two calls in a row).
struct PostedSends {
  std::vector<MPI_Request> requests;
  std::int64_t bytes = 0;
  double seconds = 0.0;  // spent posting them (counted as transfer)
};

/// The first half of neighbourExchange: checks the destinations and posts the sends.
void postNeighbourSends(const std::map<int, SendBuffer>& outgoing, std::span<const int> neighbours,
                        MPI_Comm comm, int tag, PostedSends& posted);
/// The second half: receives one message from each neighbour (the wait), completes the sends.
std::vector<Message> receiveNeighbourMessages(std::span<const int> neighbours, MPI_Comm comm,
                                              int tag, PostedSends& posted,
                                              ExchangeCost* cost = nullptr);

}  // namespace polydem::comm

#include "polydem/comm/sparse_exchange.h"

#include <algorithm>
#include <chrono>
#include <limits>

#include "polydem/core/error.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"

namespace polydem::comm {

namespace {

using Clock = std::chrono::steady_clock;

void checkSize(const SendBuffer& buffer, int rank) {
  if (buffer.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
    throw Error(cat("message of ", buffer.size(), " bytes to rank ", rank,
                    " exceeds MPI's 2 GiB count limit; use more ranks or blocks"));
  }
}

}  // namespace

std::vector<Message> sparseExchange(const std::map<int, SendBuffer>& outgoing, MPI_Comm comm,
                                    int tag, ExchangeCost* cost) {
  const auto t0 = Clock::now();
  const int ranks = mpi::size(comm);
  // Kept between calls: an exchange every step allocates only for the messages it receives.
  static thread_local std::vector<std::int64_t> send_counts, recv_counts;
  send_counts.assign(ranks, 0);
  recv_counts.assign(ranks, 0);
  std::int64_t sent = 0, messages = 0;
  for (const auto& [rank, buffer] : outgoing) {
    checkSize(buffer, rank);
    send_counts[rank] = static_cast<std::int64_t>(buffer.size());
    sent += send_counts[rank];
    messages += send_counts[rank] > 0;
  }
  MPI_Alltoall(send_counts.data(), 1, MPI_INT64_T, recv_counts.data(), 1, MPI_INT64_T, comm);
  const auto t1 = Clock::now();

  std::vector<Message> received;
  std::vector<MPI_Request> requests;
  for (int r = 0; r < ranks; ++r) {
    if (recv_counts[r] == 0) continue;
    received.push_back({r, std::vector<std::byte>(static_cast<std::size_t>(recv_counts[r]))});
  }
  requests.reserve(received.size() + outgoing.size());
  for (auto& m : received) {
    requests.emplace_back();
    MPI_Irecv(m.bytes.data(), static_cast<int>(m.bytes.size()), MPI_BYTE, m.rank, tag, comm,
              &requests.back());
  }
  for (const auto& [rank, buffer] : outgoing) {
    if (buffer.size() == 0) continue;
    requests.emplace_back();
    MPI_Isend(buffer.bytes().data(), static_cast<int>(buffer.size()), MPI_BYTE, rank, tag, comm,
              &requests.back());
  }
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
  if (cost) {
    cost->bytes += sent;
    cost->messages += messages;
    cost->wait_seconds += std::chrono::duration<double>(t1 - t0).count();
    cost->transfer_seconds += std::chrono::duration<double>(Clock::now() - t1).count();
  }
  return received;
}

void postNeighbourSends(const std::map<int, SendBuffer>& outgoing, std::span<const int> neighbours,
                        MPI_Comm comm, int tag, PostedSends& posted) {
  const auto t0 = Clock::now();
  for (const auto& [rank, buffer] : outgoing) {
    if (!std::binary_search(neighbours.begin(), neighbours.end(), rank)) {
      throw Error(cat("neighbourExchange: a message for rank ", rank, " of ", buffer.size(),
                      " bytes, which is not a neighbour of rank ", mpi::rank(comm)));
    }
    checkSize(buffer, rank);
  }
  posted.requests.assign(neighbours.size(), MPI_REQUEST_NULL);
  posted.bytes = 0;
  static const SendBuffer nothing;
  for (std::size_t k = 0; k < neighbours.size(); ++k) {
    const auto it = outgoing.find(neighbours[k]);
    const SendBuffer& buffer = it == outgoing.end() ? nothing : it->second;
    posted.bytes += static_cast<std::int64_t>(buffer.size());
    MPI_Isend(buffer.bytes().data(), static_cast<int>(buffer.size()), MPI_BYTE, neighbours[k], tag,
              comm, &posted.requests[k]);
  }
  posted.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
}

std::vector<Message> receiveNeighbourMessages(std::span<const int> neighbours, MPI_Comm comm,
                                              int tag, PostedSends& posted, ExchangeCost* cost) {
  const auto t0 = Clock::now();
  // In neighbour order: the result is sorted by source without depending on arrival order.
  std::vector<Message> received;
  double waited = 0.0;
  for (int source : neighbours) {
    const auto probe = Clock::now();
    MPI_Message handle;
    MPI_Status status;
    MPI_Mprobe(source, tag, comm, &handle, &status);
    waited += std::chrono::duration<double>(Clock::now() - probe).count();
    int count = 0;
    MPI_Get_count(&status, MPI_BYTE, &count);
    std::vector<std::byte> bytes(static_cast<std::size_t>(count));
    MPI_Mrecv(bytes.data(), count, MPI_BYTE, &handle, MPI_STATUS_IGNORE);
    if (count > 0) received.push_back({source, std::move(bytes)});
  }
  MPI_Waitall(static_cast<int>(posted.requests.size()), posted.requests.data(),
              MPI_STATUSES_IGNORE);
  if (cost) {
    const double here = std::chrono::duration<double>(Clock::now() - t0).count();
    cost->bytes += posted.bytes;
    cost->messages += static_cast<std::int64_t>(neighbours.size());
    cost->wait_seconds += waited;
    cost->transfer_seconds += posted.seconds + here - waited;
  }
  return received;
}

std::vector<Message> neighbourExchange(const std::map<int, SendBuffer>& outgoing,
                                       std::span<const int> neighbours, MPI_Comm comm, int tag,
                                       ExchangeCost* cost) {
  static thread_local PostedSends posted;
  postNeighbourSends(outgoing, neighbours, comm, tag, posted);
  return receiveNeighbourMessages(neighbours, comm, tag, posted, cost);
}

}  // namespace polydem::comm

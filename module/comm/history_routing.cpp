#include "comm/history_routing.h"

#include <algorithm>
#include <map>
#include <unordered_map>
#include <vector>

#include "comm/sparse_exchange.h"
#include "core/error.h"
#include "core/mpi_env.h"
#include "core/strings.h"

namespace polydem::comm {

namespace {

using particles::PairHistory;
using particles::PairKey;

constexpr int kRegisterTag = 7303;
constexpr int kDeliverTag = 7304;

// Record types of round 1.
constexpr std::uint8_t kOwner = 0;     // uid, owning rank
constexpr std::uint8_t kHistory = 1;   // the member uid this directory answers for, then the pair
constexpr std::uint8_t kEveryone = 2;  // a pair of two replicated particles: keep it

int directoryOf(Uid uid, int ranks) {
  return static_cast<int>(uid % static_cast<Uid>(ranks));
}

}  // namespace

particles::ContactHistory routeHistories(std::span<const PairKey> keys,
                                         std::span<const PairHistory> entries,
                                         std::span<const Uid> owned,
                                         std::span<const Uid> replicated, MPI_Comm comm,
                                         HistoryRoutingStats* stats) {
  if (keys.size() != entries.size()) {
    throw Error(cat("routeHistories: ", keys.size(), " keys but ", entries.size(), " histories"));
  }
  const int rank = mpi::rank(comm), ranks = mpi::size(comm);
  std::vector<Uid> everywhere(replicated.begin(), replicated.end());
  std::sort(everywhere.begin(), everywhere.end());
  auto isReplicated = [&](Uid u) {
    return std::binary_search(everywhere.begin(), everywhere.end(), u);
  };
  HistoryRoutingStats local_stats;

  // Round 1: owners and histories meet at the directories.
  std::map<int, SendBuffer> outgoing;
  for (Uid u : owned) {
    outgoing[directoryOf(u, ranks)] << kOwner << u << static_cast<std::int32_t>(rank);
    ++local_stats.registered;
  }
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const PairKey& k = keys[i];
    const bool lo_everywhere = isReplicated(k.lo), hi_everywhere = isReplicated(k.hi);
    if (lo_everywhere && hi_everywhere) {
      for (int r = 0; r < ranks; ++r) {
        outgoing[r] << kEveryone;
        pack(outgoing[r], k, entries[i]);
      }
      continue;
    }
    for (Uid member : {k.lo, k.hi}) {
      if (isReplicated(member)) continue;
      SendBuffer& out = outgoing[directoryOf(member, ranks)];
      out << kHistory << member;
      pack(out, k, entries[i]);
    }
  }
  std::unordered_map<Uid, int> owner_of;
  std::vector<std::pair<Uid, std::pair<PairKey, PairHistory>>> waiting;  // (member, pair)
  std::vector<PairKey> kept_keys;
  std::vector<PairHistory> kept_entries;
  std::int64_t problems = 0;
  Uid example = 0;
  for (const auto& m : sparseExchange(outgoing, comm, kRegisterTag)) {
    RecvBuffer in(m.bytes.data(), m.bytes.size());
    while (!in.atEnd()) {
      std::uint8_t type = 0;
      in >> type;
      if (type == kOwner) {
        Uid u = 0;
        std::int32_t owner = 0;
        in >> u >> owner;
        if (!owner_of.emplace(u, owner).second) {
          ++problems;  // owned by two ranks
          example = u;
        }
      } else {
        Uid member = 0;
        if (type == kHistory) in >> member;
        PairKey k;
        PairHistory h;
        unpack(in, k, h);
        if (type == kHistory) {
          waiting.push_back({member, {k, h}});
        } else {
          kept_keys.push_back(k);
          kept_entries.push_back(h);
        }
      }
    }
  }

  // Round 2: each directory forwards to the owners.
  outgoing.clear();
  for (const auto& [member, pair] : waiting) {
    const auto it = owner_of.find(member);
    if (it == owner_of.end()) {
      ++problems;  // a pair with a particle nobody owns
      example = member;
      continue;
    }
    pack(outgoing[it->second], pair.first, pair.second);
    ++local_stats.forwarded;
  }
  for (const auto& m : sparseExchange(outgoing, comm, kDeliverTag)) {
    RecvBuffer in(m.bytes.data(), m.bytes.size());
    while (!in.atEnd()) {
      PairKey k;
      PairHistory h;
      unpack(in, k, h);
      kept_keys.push_back(k);
      kept_entries.push_back(h);
    }
  }
  const std::int64_t total_problems = mpi::allreduceSum(problems, comm);
  if (total_problems > 0) {
    Uid first = problems > 0 ? example : ~Uid{0};
    MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_UINT64_T, MPI_MIN, comm);
    throw Error(cat("routeHistories: ", total_problems,
                    " pair histories or uids without exactly one owner (e.g. particle uid ", first,
                    ")"));
  }
  // Copies of one pair (from its two directories) are the same record: merge keeps one.
  particles::ContactHistory out;
  out.merge(kept_keys, kept_entries);
  local_stats.kept = static_cast<std::int64_t>(out.size());
  if (stats) *stats = local_stats;
  return out;
}

particles::ContactHistory routeHistories(std::span<const PairKey> keys,
                                         std::span<const PairHistory> entries,
                                         const particles::ParticleStorage& storage, MPI_Comm comm,
                                         HistoryRoutingStats* stats) {
  std::vector<Uid> owned, replicated;
  for (std::size_t i = 0; i < storage.localCount(); ++i) {
    const auto& p = storage[i];
    (p.isGlobal() ? replicated : owned).push_back(p.uid);
  }
  return routeHistories(keys, entries, owned, replicated, comm, stats);
}

}  // namespace polydem::comm

// Routing pair histories to the ranks that need them, e.g. after reading a checkpoint: each rank
// read an arbitrary slice of the pair histories, the particles have been migrated to their owners,
// and now every history must reach every rank owning its lo or its hi particle.
//
// No rank knows who owns a uid, so the histories meet the owners at a directory: rank uid % P.
//   round 1: every rank registers its owned uids at their directory ranks, and sends each history
//            to the directory of each of its two particles;
//   round 2: each directory forwards the histories it received to the owners registered with it.
// A rank owning both particles of a pair receives it twice and keeps one copy. Replicated
// (fixed/driven) particles are on every rank and have no owner: a pair with one of them goes to
// the owner of its other particle, and a pair of two of them to every rank.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include "polydem/core/types.h"
#include "polydem/particles/contact_history.h"
#include "polydem/particles/particle_storage.h"

namespace polydem::comm {

struct HistoryRoutingStats {
  std::int64_t registered = 0;  // uids this rank registered at their directories
  std::int64_t forwarded = 0;   // histories this rank forwarded as a directory
  std::int64_t kept = 0;        // histories this rank holds afterwards
  std::int64_t chunks = 0;      // route() calls
  /// The most bytes one chunk's routing held on this rank at once: the messages sent and
  /// received in both rounds and the records waiting at the directory and kept (capacities).
  /// Bounded by the chunk size, whatever the size of the whole history.
  std::uint64_t peak_transit_bytes = 0;
};

/// Routing in chunks, so that the records in transit stay bounded: the owners register at their
/// directories once, then each route() delivers one chunk of every rank's records to their
/// owners and appends them to this rank's history (ContactHistory::appendRecords), which finish()
/// sorts once (ContactHistory::endAssembly). A round costs what its records cost, whatever the
/// size of the history or the particle count.
class HistoryRouter {
 public:
  /// Collective. `owned`: uids of the free particles this rank owns; `replicated`: uids of the
  /// fixed/driven particles, the same on every rank. Throws polydem::Error on every rank if a uid
  /// is owned by two ranks.
  HistoryRouter(std::span<const Uid> owned, std::span<const Uid> replicated, MPI_Comm comm);
  /// The same, with `owned` and `replicated` taken from the storage's local particles.
  HistoryRouter(const particles::ParticleStorage& storage, MPI_Comm comm);

  /// Collective: every rank calls it equally often (with an empty chunk when it has no records
  /// left). Delivers the chunks' records to every rank owning the lo or the hi particle of their
  /// pair and appends them to `into`, whose assembly the caller has begun
  /// (ContactHistory::beginAssembly). Throws polydem::Error on every rank if a pair names a free
  /// particle that no rank owns.
  void route(const particles::HistoryRecords& chunk, particles::ContactHistory& into);
  /// Ends the assembly of `into` (ContactHistory::endAssembly): the table sorted, one copy of
  /// each key (a rank owning both particles of a pair receives it twice).
  void finish(particles::ContactHistory& into);

  const HistoryRoutingStats& stats() const { return stats_; }

 private:
  MPI_Comm comm_;
  int rank_ = 0, ranks_ = 1;
  std::vector<Uid> replicated_;            // sorted
  std::unordered_map<Uid, int> owner_of_;  // the uids this rank is the directory of
  HistoryRoutingStats stats_;
};

/// Delivers the histories (`keys[i]`, `entries[i]`) of all ranks to every rank that owns the lo
/// or the hi particle of the pair. `owned`: uids of the free particles this rank owns.
/// `replicated`: uids of the fixed/driven particles, the same on every rank. Returns this rank's
/// histories, sorted by key, each pair once. Collective; throws polydem::Error on every rank if a
/// pair names a free particle that no rank owns, or a uid is owned by two ranks.
particles::ContactHistory routeHistories(std::span<const particles::PairKey> keys,
                                         std::span<const particles::PairHistory> entries,
                                         std::span<const Uid> owned,
                                         std::span<const Uid> replicated, MPI_Comm comm,
                                         HistoryRoutingStats* stats = nullptr);

/// The same for pairs and their sub-contacts (particles/contact_history.h): a sub-contact's
/// history goes wherever its pair's goes.
particles::ContactHistory routeHistories(const particles::HistoryRecords& records,
                                         std::span<const Uid> owned,
                                         std::span<const Uid> replicated, MPI_Comm comm,
                                         HistoryRoutingStats* stats = nullptr);

/// The same, with `owned` and `replicated` taken from the storage's local (non-ghost) particles.
particles::ContactHistory routeHistories(std::span<const particles::PairKey> keys,
                                         std::span<const particles::PairHistory> entries,
                                         const particles::ParticleStorage& storage, MPI_Comm comm,
                                         HistoryRoutingStats* stats = nullptr);
particles::ContactHistory routeHistories(const particles::HistoryRecords& records,
                                         const particles::ParticleStorage& storage, MPI_Comm comm,
                                         HistoryRoutingStats* stats = nullptr);

}  // namespace polydem::comm

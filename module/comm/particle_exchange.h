// Migration and ghost exchange over the block forest.
//
// After each integration step, exchange() does both in one message per neighbour rank:
//  - a free particle whose centroid left this rank's blocks goes to the rank owning the block it
//    is now in, together with the contact history of every pair it belongs to (along periodic
//    axes the centroid is wrapped back into the domain first);
//  - every free particle is copied, as a ghost, to every rank other than its (new) owner that owns
//    a block within its ghost radius (own circumradius + the largest circumradius of any free
//    particle + the contact margin), and to its owner itself as a shifted image across periodic
//    faces. The rank that held the particle before the step sends its ghosts, so a particle that
//    migrates needs no second round.
// migrate() and refreshGhosts() do the two halves separately (restart, rebalancing, tests); they
// give the same particles, ghosts and histories.
// The message of exchange() goes to the neighbour ranks only (those owning a block within three
// ghost ranges of this rank's blocks, domain::BlockForest::ranksWithin), each of which gets one
// even if it is empty, so that no collective is needed to agree on the message sizes; a particle
// that would have to go further (it moved more than the ghost range in one step) stops the run
// with a SimulationError. The first exchange, and one after the forest changed, use a collective
// sparse exchange instead. A ghost that stays a ghost on the same rank travels as a state update
// (ghost_channels.h).
// Fixed and driven particles are replicated on all ranks and never move between them.
// A pair whose two particles live on two ranks is evaluated on both, from identical inputs, so
// no force is sent back; the ghost radius above guarantees each owner sees all its partners.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <map>
#include <vector>

#include "polydem/comm/ghost_channels.h"
#include "polydem/comm/sparse_exchange.h"
#include "polydem/domain/block_forest.h"
#include "polydem/particles/contact_history.h"
#include "polydem/particles/particle_storage.h"

namespace polydem::comm {

struct ExchangeStats {
  std::int64_t particles_sent = 0, particles_received = 0;          // ghosts included
  std::int64_t ghost_updates_sent = 0, ghost_updates_received = 0;  // of those: state updates
  std::int64_t histories_sent = 0, histories_received = 0;
  std::int64_t history_conflicts = 0;  // received copies that differ from ours: must stay 0
  std::int64_t bytes_sent = 0;
  std::int64_t messages_sent = 0;
  // Time: the whole call, and within it the wait for the slowest rank and the transfer proper
  // (ExchangeCost); the rest is bookkeeping (finding destinations, packing, unpacking).
  double seconds = 0.0, wait_seconds = 0.0, transfer_seconds = 0.0;

  ExchangeStats& operator+=(const ExchangeStats& o) {
    particles_sent += o.particles_sent;
    particles_received += o.particles_received;
    ghost_updates_sent += o.ghost_updates_sent;
    ghost_updates_received += o.ghost_updates_received;
    histories_sent += o.histories_sent;
    histories_received += o.histories_received;
    history_conflicts += o.history_conflicts;
    bytes_sent += o.bytes_sent;
    messages_sent += o.messages_sent;
    seconds += o.seconds;
    wait_seconds += o.wait_seconds;
    transfer_seconds += o.transfer_seconds;
    return *this;
  }
};

class ParticleExchange {
 public:
  explicit ParticleExchange(MPI_Comm comm);

  /// Heap bytes of its messages in flight, ghost channels and scratch (capacities,
  /// core/memory.h; map nodes not counted).
  std::uint64_t heapBytes() const;

  /// Moves particles to their owners (see above). Drops ghosts first. Throws SimulationError if a
  /// particle left the domain along a non-periodic axis. Collective.
  ExchangeStats migrate(const domain::BlockForest& forest, particles::ParticleStorage& storage,
                        particles::ContactHistory& history, std::int64_t step);

  /// migrate() and refreshGhosts() in one sparse exchange: one message per neighbour rank.
  /// Collective.
  ExchangeStats exchange(const domain::BlockForest& forest, particles::ParticleStorage& storage,
                         particles::ContactHistory& history, const particles::ShapeTable& shapes,
                         double range, std::int64_t step);

  /// exchange() in two halves, so that work on the local particles can run while the messages
  /// travel. post() does everything up to the sends: the migrants are gone from `storage`, the
  /// ghosts dropped, positions wrapped; it returns true if messages to neighbours are in flight
  /// (false: one rank, or a collective exchange that completed at once). finish() receives,
  /// unpacks the arrivals (appended after the local particles, whose indices stay), merges their
  /// histories into `history` and adds the ghosts: then the state is what exchange() leaves. Both
  /// collective; nothing else may touch `storage` or `history` in between except to read them.
  bool post(const domain::BlockForest& forest, particles::ParticleStorage& storage,
            particles::ContactHistory& history, const particles::ShapeTable& shapes, double range,
            std::int64_t step);
  ExchangeStats finish(const domain::BlockForest& forest, particles::ParticleStorage& storage,
                       particles::ContactHistory& history);

  /// False: every ghost travels whole at every exchange (the same ghosts, more bytes); for
  /// comparisons. Collective in effect: set it alike on every rank.
  void setCompactGhosts(bool on) { channels_.setCompact(on); }

  /// Replaces all ghosts by fresh copies. `range` is added to each particle's own circumradius
  /// to get its ghost radius (the largest free circumradius plus the contact margin). Collective.
  ExchangeStats refreshGhosts(const domain::BlockForest& forest,
                              particles::ParticleStorage& storage,
                              const particles::ShapeTable& shapes, double range);

 private:
  /// The neighbours are the ranks within this many ghost ranges (see above).
  static constexpr double kNeighbourReach = 3.0;

  /// The forest (and ghost range) that the local particles were last placed by: while the
  /// exchange is given the same, each particle can only go to a neighbour.
  struct Placement {
    bool valid = false;
    double range = 0.0;
    domain::Index3 counts{};
    domain::Periodic periodic{};
    Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
    std::vector<int> rank_map;
    bool matches(const domain::BlockForest& forest, double range) const;
  };
  void placed(const domain::BlockForest& forest, double range);
  /// `rank`, checked to be a neighbour when only neighbours are talked to.
  int destination(int rank, const particles::Particle& p, std::int64_t step,
                  bool neighbours_only) const;

  /// An exchange between post() and finish().
  struct InFlight {
    bool posted = false, neighbours_only = false;
    std::map<int, SendBuffer> outgoing;                           // alive until the sends complete
    std::vector<std::pair<particles::Particle, Vec3>> kept_here;  // ghosts kept on this rank
    PostedSends sends;
    std::vector<Message> received;
    ExchangeStats stats;
    double seconds = 0.0;  // spent in post()
  };

  MPI_Comm comm_;
  int rank_ = 0;
  InFlight in_flight_;
  std::vector<domain::RankHit> hits_;  // reused between calls
  GhostChannels channels_;
  Placement placement_;
  std::vector<int> neighbours_;  // sorted
};

}  // namespace polydem::comm

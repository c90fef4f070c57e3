#include "polydem/comm/particle_exchange.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <unordered_map>

#include "polydem/comm/sparse_exchange.h"
#include "polydem/core/error.h"
#include "polydem/core/memory.h"
#include "polydem/core/mpi_env.h"
#include "polydem/core/strings.h"

namespace polydem::comm {

namespace {

constexpr int kMigrateTag = 7301;
constexpr int kGhostTag = 7302;
constexpr int kExchangeTag = 7305;

// Record types of a message, after its ghost section (ghost_channels.h).
constexpr std::uint8_t kParticleRecord = 0;  // a particle that now belongs to the receiver
constexpr std::uint8_t kHistoryRecord = 1;   // a pair history travelling with it
constexpr std::uint8_t kSubRecord = 3;       // a sub-contact history of a pair sent with it

using particles::ContactHistory;
using particles::PairHistory;
using particles::PairKey;
using particles::Particle;
using Clock = std::chrono::steady_clock;

template <typename Key, typename Entry>
bool sameBits(const Entry& a, const Entry& b) {
  SendBuffer x, y;
  pack(x, Key{}, a);
  pack(y, Key{}, b);
  return x.bytes() == y.bytes();
}

// Wraps the centroid back into the domain along periodic axes and returns its owner rank.
int ownerAfterWrap(const domain::BlockForest& forest, Particle& p, std::int64_t step) {
  const auto& per = forest.periodic();
  if (per[0] || per[1] || per[2]) p.position = forest.wrap(p.position);
  const int block = forest.blockOf(p.position);
  if (block < 0) {
    const auto& box = forest.domain();
    throw SimulationError(cat("particle ", p.uid, " left the domain at (", p.position.x(), ", ",
                              p.position.y(), ", ", p.position.z(), ") at step ", step,
                              "; the domain is [", box.lo.x(), ", ", box.hi.x(), "] x [",
                              box.lo.y(), ", ", box.hi.y(), "] x [", box.lo.z(), ", ", box.hi.z(),
                              "]: enlarge [domain] min/max in the scene"));
  }
  return forest.rankOfBlock(block);
}

// Packs local particle i for `owner`, the rank that owns it now, and removes it here (particle i
// is then the next one); its pairs' histories follow through `leaving` (packHistories).
void sendToOwner(particles::ParticleStorage& storage, std::size_t i, int owner,
                 std::map<int, SendBuffer>& outgoing, std::unordered_map<Uid, int>& leaving,
                 ExchangeStats& stats) {
  const Particle& p = storage[i];
  leaving.emplace(p.uid, owner);
  SendBuffer& out = outgoing[owner];
  out << kParticleRecord;
  pack(out, p);
  ++stats.particles_sent;
  storage.removeLocal(i);
}

// The histories of every pair a leaving particle belongs to, to its destination (once per
// destination when both members leave to the same rank).
void packHistories(const ContactHistory& history, const std::unordered_map<Uid, int>& leaving,
                   std::map<int, SendBuffer>& outgoing, ExchangeStats& stats) {
  if (leaving.empty()) return;
  const auto keys = history.keys();
  const auto entries = history.entries();
  for (std::size_t k = 0; k < keys.size(); ++k) {
    for (Uid uid : {keys[k].lo, keys[k].hi}) {
      const auto it = leaving.find(uid);
      if (it == leaving.end()) continue;
      if (uid == keys[k].hi) {  // both members leaving to the same rank: send once
        const auto lo = leaving.find(keys[k].lo);
        if (lo != leaving.end() && lo->second == it->second) continue;
      }
      SendBuffer& out = outgoing[it->second];
      out << kHistoryRecord;
      pack(out, keys[k], entries[k]);
      const auto [first, last] = history.subsOf(k);
      for (std::size_t s = first; s < last; ++s) {
        out << kSubRecord;
        pack(out, particles::SubKey{keys[k], history.subFeatures()[s].feature},
             history.subEntries()[s]);
      }
      ++stats.histories_sent;
    }
  }
}

// Unpacks received messages: the ghost section into `channels`, then the records: particles
// become local at once, histories are merged.
void unpackMessages(const std::vector<Message>& messages, particles::ParticleStorage& storage,
                    ContactHistory& history, GhostChannels& channels, ExchangeStats& stats) {
  particles::HistoryRecords received;
  for (const auto& m : messages) {
    RecvBuffer in(m.bytes.data(), m.bytes.size());
    const GhostCounts ghosts = channels.unpack(m.rank, in);
    stats.particles_received += ghosts.whole + ghosts.updates;
    stats.ghost_updates_received += ghosts.updates;
    while (!in.atEnd()) {
      std::uint8_t type = 0;
      in >> type;
      if (type == kParticleRecord) {
        Particle p;
        unpack(in, p);
        storage.addLocal(p);
        ++stats.particles_received;
      } else if (type == kHistoryRecord) {
        PairKey key;
        PairHistory h;
        unpack(in, key, h);
        if (const PairHistory* mine = history.find(key);
            mine && !sameBits<PairKey, PairHistory>(*mine, h)) {
          ++stats.history_conflicts;
        }
        received.keys.push_back(key);
        received.entries.push_back(h);
        ++stats.histories_received;
      } else if (type == kSubRecord) {
        particles::SubKey key;
        particles::SubHistory h;
        unpack(in, key, h);
        received.sub_keys.push_back(key);
        received.sub_entries.push_back(h);
      } else {
        throw Error(cat("message from rank ", m.rank, " has an unknown record type ", int{type}));
      }
    }
  }
  if (!received.empty()) history.merge(std::move(received));
}

// Ghosts into the storage once every local particle is in: those kept here first (periodic self
// images, ghosts of particles that just left), then the received ones by source rank.
void addGhosts(const std::vector<std::pair<Particle, Vec3>>& kept_here,
               const GhostChannels& channels, const domain::BlockForest& forest,
               particles::ParticleStorage& storage) {
  for (const auto& [p, shift] : kept_here) storage.addGhost(p, shift);
  channels.forEachHeld([&](const Particle& p, const domain::Index3& image) {
    storage.addGhost(p, forest.imageShift(image));
  });
}

void addCost(ExchangeStats& stats, const ExchangeCost& cost) {
  stats.bytes_sent += cost.bytes;
  stats.messages_sent += cost.messages;
  stats.wait_seconds += cost.wait_seconds;
  stats.transfer_seconds += cost.transfer_seconds;
}

}  // namespace

ParticleExchange::ParticleExchange(MPI_Comm comm) : comm_(comm), rank_(mpi::rank(comm)) {}

bool ParticleExchange::Placement::matches(const domain::BlockForest& forest, double r) const {
  const auto& d = forest.domain();
  return valid && range == r && counts == forest.counts() && periodic == forest.periodic() &&
         lo == d.lo && hi == d.hi && rank_map == forest.rankMap();
}

// Every local particle now stands in this rank's blocks of `forest`: the next exchange may talk to
// the neighbours alone. A particle goes from here to the rank owning its new centroid and to the
// ranks within its ghost radius of it; that radius (own circumradius + range) is at most 2 range,
// so the neighbours within 3 range take it as long as it moved at most `range` in the step.
void ParticleExchange::placed(const domain::BlockForest& forest, double range) {
  const auto& d = forest.domain();
  placement_ = {true, range, forest.counts(), forest.periodic(), d.lo, d.hi, forest.rankMap()};
  neighbours_.clear();
  if (forest.numRanks() > 1) neighbours_ = forest.ranksWithin(rank_, kNeighbourReach * range);
}

int ParticleExchange::destination(int rank, const Particle& p, std::int64_t step,
                                  bool neighbours_only) const {
  if (!neighbours_only || rank == rank_ ||
      std::binary_search(neighbours_.begin(), neighbours_.end(), rank)) {
    return rank;
  }
  throw SimulationError(cat("particle ", p.uid, " at (", p.position.x(), ", ", p.position.y(), ", ",
                            p.position.z(), ") at step ", step, " must go from rank ", rank_,
                            " to rank ", rank, ", which owns no block within ",
                            kNeighbourReach * placement_.range, " of rank ", rank_,
                            "'s blocks: it moved more than the ghost range (", placement_.range,
                            ") in one step; reduce dt"));
}

ExchangeStats ParticleExchange::migrate(const domain::BlockForest& forest,
                                        particles::ParticleStorage& storage,
                                        ContactHistory& history, std::int64_t step) {
  const auto t0 = Clock::now();
  ExchangeStats stats;
  storage.dropGhosts();
  channels_.reset();
  std::map<int, SendBuffer> records, outgoing;
  std::unordered_map<Uid, int> leaving;  // uid -> destination rank
  for (std::size_t i = 0; i < storage.size();) {
    Particle& p = storage[i];
    if (p.isGlobal()) {
      ++i;
      continue;
    }
    const int owner = ownerAfterWrap(forest, p, step);
    if (owner == rank_) {
      ++i;
      continue;
    }
    sendToOwner(storage, i, owner, records, leaving, stats);
  }
  packHistories(history, leaving, records, stats);
  channels_.pack(records, outgoing);
  ExchangeCost cost;
  const auto messages = sparseExchange(outgoing, comm_, kMigrateTag, &cost);
  addCost(stats, cost);
  unpackMessages(messages, storage, history, channels_, stats);
  if (placement_.valid) placed(forest, placement_.range);  // range: the exchange's own
  stats.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return stats;
}

ExchangeStats ParticleExchange::refreshGhosts(const domain::BlockForest& forest,
                                              particles::ParticleStorage& storage,
                                              const particles::ShapeTable& shapes, double range) {
  const auto t0 = Clock::now();
  ExchangeStats stats;
  storage.dropGhosts();
  channels_.reset();
  std::vector<std::pair<Particle, Vec3>> kept_here;  // periodic self images
  for (std::size_t i = 0; i < storage.localCount(); ++i) {
    const Particle& p = storage[i];
    if (p.isGlobal()) continue;
    const double radius = shapes[p.shape].circumradius + range;
    if (forest.sphereWithinRank(p.position, radius, rank_)) continue;  // no ghost anywhere
    forest.ranksIntersectingSphere(p.position, radius, hits_);
    for (const auto& hit : hits_) {
      const bool unshifted = hit.shift.isZero(0.0);
      if (hit.rank == rank_) {
        if (!unshifted) kept_here.emplace_back(p, hit.shift);
        continue;
      }
      channels_.queue(hit.rank, p, hit.image);
      ++stats.particles_sent;
    }
  }
  std::map<int, SendBuffer> outgoing;
  channels_.pack({}, outgoing);
  ExchangeCost cost;
  const auto messages = sparseExchange(outgoing, comm_, kGhostTag, &cost);
  addCost(stats, cost);
  ContactHistory unused;
  unpackMessages(messages, storage, unused, channels_, stats);
  addGhosts(kept_here, channels_, forest, storage);
  stats.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return stats;
}

ExchangeStats ParticleExchange::exchange(const domain::BlockForest& forest,
                                         particles::ParticleStorage& storage,
                                         ContactHistory& history,
                                         const particles::ShapeTable& shapes, double range,
                                         std::int64_t step) {
  post(forest, storage, history, shapes, range, step);
  return finish(forest, storage, history);
}

bool ParticleExchange::post(const domain::BlockForest& forest, particles::ParticleStorage& storage,
                            ContactHistory& history, const particles::ShapeTable& shapes,
                            double range, std::int64_t step) {
  if (in_flight_.posted) throw Error("ParticleExchange::post: the last exchange is not finished");
  const auto t0 = Clock::now();
  ExchangeStats& stats = in_flight_.stats;
  stats = {};
  in_flight_.kept_here.clear();
  in_flight_.outgoing.clear();
  storage.dropGhosts();
  // The neighbours alone, unless the particles were placed by another forest (a rebalance, the
  // first exchange): then any rank may receive, and every ghost travels whole.
  const bool neighbours_only = placement_.matches(forest, range);
  if (!neighbours_only) channels_.reset();
  std::map<int, SendBuffer> records;
  std::unordered_map<Uid, int> leaving;    // uid -> destination rank
  auto& kept_here = in_flight_.kept_here;  // ghosts kept on this rank
  // One rank and no periodic axis: no ghosts at all, and no sphere queries to find that out.
  const auto& periodic = forest.periodic();
  const bool alone = forest.numRanks() == 1 && !periodic[0] && !periodic[1] && !periodic[2];
  for (std::size_t i = 0; i < storage.size();) {
    Particle& p = storage[i];
    if (p.isGlobal()) {
      ++i;
      continue;
    }
    const int owner = destination(ownerAfterWrap(forest, p, step), p, step, neighbours_only);
    if (alone) {
      ++i;
      continue;
    }
    // The ghosts of the particle where it now stands, sent by the rank that moved it: to every
    // hit but its owner's own unshifted copy. A hit on this rank is kept here: a periodic self
    // image, or a ghost of a particle that just left for a neighbour. Most particles' ghost
    // spheres stay inside their owner's blocks: no hit to send, and no query to find that out.
    const double radius = shapes[p.shape].circumradius + range;
    if (forest.sphereWithinRank(p.position, radius, owner)) {
      hits_.clear();
    } else {
      forest.ranksIntersectingSphere(p.position, radius, hits_);
    }
    for (const auto& hit : hits_) {
      if (hit.rank == owner && hit.shift.isZero(0.0)) continue;
      if (hit.rank == rank_) {
        kept_here.emplace_back(p, hit.shift);
      } else {
        channels_.queue(destination(hit.rank, p, step, neighbours_only), p, hit.image);
        ++stats.particles_sent;
      }
    }
    if (owner == rank_) {
      ++i;
      continue;
    }
    sendToOwner(storage, i, owner, records, leaving, stats);
  }
  packHistories(history, leaving, records, stats);
  stats.ghost_updates_sent = channels_.pack(records, in_flight_.outgoing).updates;
  in_flight_.posted = true;
  in_flight_.neighbours_only = neighbours_only;
  if (neighbours_only) {
    postNeighbourSends(in_flight_.outgoing, neighbours_, comm_, kExchangeTag, in_flight_.sends);
  } else {
    // A collective exchange to any rank: nothing to overlap, it completes here.
    ExchangeCost cost;
    in_flight_.received = sparseExchange(in_flight_.outgoing, comm_, kExchangeTag, &cost);
    addCost(stats, cost);
  }
  in_flight_.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  if (!neighbours_only) placed(forest, range);
  return neighbours_only && !neighbours_.empty();
}

ExchangeStats ParticleExchange::finish(const domain::BlockForest& forest,
                                       particles::ParticleStorage& storage,
                                       ContactHistory& history) {
  if (!in_flight_.posted) throw Error("ParticleExchange::finish: no exchange was posted");
  const auto t0 = Clock::now();
  ExchangeStats& stats = in_flight_.stats;
  if (in_flight_.neighbours_only) {
    ExchangeCost cost;
    in_flight_.received =
        receiveNeighbourMessages(neighbours_, comm_, kExchangeTag, in_flight_.sends, &cost);
    addCost(stats, cost);
  }
  unpackMessages(in_flight_.received, storage, history, channels_, stats);
  addGhosts(in_flight_.kept_here, channels_, forest, storage);
  in_flight_.received.clear();
  in_flight_.posted = false;
  // The exchange's own time: what ran between post() and finish() is not its.
  stats.seconds = in_flight_.seconds + std::chrono::duration<double>(Clock::now() - t0).count();
  return stats;
}

std::uint64_t ParticleExchange::heapBytes() const {
  std::uint64_t bytes = capacityBytes(in_flight_.kept_here) + capacityBytes(in_flight_.received) +
                        capacityBytes(in_flight_.sends.requests) + capacityBytes(hits_) +
                        capacityBytes(placement_.rank_map) + capacityBytes(neighbours_) +
                        channels_.heapBytes();
  for (const auto& [rank, buffer] : in_flight_.outgoing) bytes += capacityBytes(buffer.bytes());
  for (const auto& m : in_flight_.received) bytes += capacityBytes(m.bytes);
  return bytes;
}

}  // namespace polydem::comm

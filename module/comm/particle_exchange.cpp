#include "comm/particle_exchange.h"

#include <algorithm>
#include <map>
#include <unordered_map>

#include "comm/sparse_exchange.h"
#include "core/error.h"
#include "core/mpi_env.h"
#include "core/strings.h"

namespace polydem::comm {

namespace {

constexpr int kMigrateTag = 7301;
constexpr int kGhostTag = 7302;

using particles::ContactHistory;
using particles::PairHistory;
using particles::PairKey;
using particles::Particle;

template <typename Key, typename Entry>
bool sameBits(const Entry& a, const Entry& b) {
  SendBuffer x, y;
  pack(x, Key{}, a);
  pack(y, Key{}, b);
  return x.bytes() == y.bytes();
}

// Record types of a migration message.
constexpr std::uint8_t kParticleRecord = 0;
constexpr std::uint8_t kPairRecord = 1;
constexpr std::uint8_t kSubRecord = 2;

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

}  // namespace

ParticleExchange::ParticleExchange(MPI_Comm comm) : comm_(comm), rank_(mpi::rank(comm)) {}

ExchangeStats ParticleExchange::migrate(const domain::BlockForest& forest,
                                        particles::ParticleStorage& storage,
                                        ContactHistory& history, std::int64_t step) {
  ExchangeStats stats;
  storage.dropGhosts();
  std::map<int, SendBuffer> outgoing;
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
    leaving.emplace(p.uid, owner);
    SendBuffer& out = outgoing[owner];
    out << kParticleRecord;
    pack(out, p);
    ++stats.particles_sent;
    storage.removeLocal(i);
  }
  if (!leaving.empty()) {
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
        out << kPairRecord;
        pack(out, keys[k], entries[k]);
        const auto [first, last] = history.subRange(keys[k]);
        for (std::size_t s = first; s < last; ++s) {
          out << kSubRecord;
          pack(out, history.subKeys()[s], history.subEntries()[s]);
        }
        ++stats.histories_sent;
      }
    }
  }
  const auto messages = sparseExchange(outgoing, comm_, kMigrateTag, &stats.bytes_sent);
  particles::HistoryRecords received;
  for (const auto& m : messages) {
    RecvBuffer in(m.bytes.data(), m.bytes.size());
    while (!in.atEnd()) {
      std::uint8_t type = 0;
      in >> type;
      if (type == kParticleRecord) {
        Particle p;
        unpack(in, p);
        storage.addLocal(p);
        ++stats.particles_received;
      } else if (type == kPairRecord) {
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
      } else {
        particles::SubKey key;
        particles::SubHistory h;
        unpack(in, key, h);
        received.sub_keys.push_back(key);
        received.sub_entries.push_back(h);
      }
    }
  }
  if (!received.empty()) history.merge(received);
  return stats;
}

ExchangeStats ParticleExchange::refreshGhosts(const domain::BlockForest& forest,
                                              particles::ParticleStorage& storage,
                                              const particles::ShapeTable& shapes, double range) {
  ExchangeStats stats;
  storage.dropGhosts();
  std::map<int, SendBuffer> outgoing;
  std::vector<std::pair<Particle, Vec3>> self_images;
  for (std::size_t i = 0; i < storage.localCount(); ++i) {
    const Particle& p = storage[i];
    if (p.isGlobal()) continue;
    const double radius = shapes[p.shape].circumradius + range;
    forest.ranksIntersectingSphere(p.position, radius, hits_);
    for (const auto& hit : hits_) {
      const bool unshifted = hit.shift.isZero(0.0);
      if (hit.rank == rank_) {
        if (!unshifted) self_images.emplace_back(p, hit.shift);
        continue;
      }
      SendBuffer& out = outgoing[hit.rank];
      pack(out, p);
      out << hit.shift;
      ++stats.particles_sent;
    }
  }
  const auto messages = sparseExchange(outgoing, comm_, kGhostTag, &stats.bytes_sent);
  for (const auto& [p, shift] : self_images) storage.addGhost(p, shift);
  for (const auto& m : messages) {
    RecvBuffer in(m.bytes.data(), m.bytes.size());
    while (!in.atEnd()) {
      Particle p;
      Vec3 shift;
      unpack(in, p);
      in >> shift;
      storage.addGhost(p, shift);
      ++stats.particles_received;
    }
  }
  return stats;
}

}  // namespace polydem::comm

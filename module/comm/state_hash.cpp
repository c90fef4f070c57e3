#include "polydem/comm/state_hash.h"

#include <algorithm>

#include "polydem/core/mpi_env.h"
#include "polydem/core/state_hash.h"

namespace polydem::comm {

namespace {

struct Keyed {
  Uid a = 0, b = 0;
  std::uint64_t hash = 0;
  bool operator<(const Keyed& o) const {
    return a != o.a ? a < o.a : (b != o.b ? b < o.b : hash < o.hash);
  }
};

// Over the pair's history and, with the sub-contact model, its sub-contacts' (a pair without any
// hashes as it did before sub-contacts existed). A sub-contact's joint-law history values are
// hashed when one is not 0, so that a run without such laws hashes as it did before they existed.
std::uint64_t historyHash(const particles::PairKey& key, const particles::PairHistory& h,
                          std::span<const particles::SubFeature> sub_keys,
                          std::span<const particles::SubHistory> subs) {
  SendBuffer bytes;
  pack(bytes, key, h);
  for (std::size_t i = 0; i < sub_keys.size(); ++i) {
    const particles::SubHistory& s = subs[i];
    bytes << key.lo << key.hi << sub_keys[i].feature << s.shear_force << s.normal;
    if (s.hasLawState()) bytes << s.law[0] << s.law[1];
  }
  BitHasher hasher;
  const auto& raw = bytes.bytes();
  for (std::size_t i = 0; i < raw.size(); i += 8) {
    std::uint64_t word = 0;
    std::memcpy(&word, raw.data() + i, std::min<std::size_t>(8, raw.size() - i));
    hasher.add(word);
  }
  return hasher.value();
}

}  // namespace

std::string StateHash::hex() const {
  return BitHasher::hex(combined);
}

std::uint64_t particleHash(const particles::Particle& p) {
  BitHasher h;
  h.add(static_cast<std::uint64_t>(p.uid));
  h.add(static_cast<std::uint64_t>(static_cast<std::uint32_t>(p.shape)));
  h.add(static_cast<std::uint64_t>(static_cast<std::uint32_t>(p.material)));
  h.add(static_cast<std::uint64_t>(p.flags & ~particles::kGhost));
  h.add(static_cast<std::uint64_t>(static_cast<std::uint32_t>(p.driver)));
  h.add(p.position);
  h.add(p.orientation);
  h.add(p.velocity);
  h.add(p.angular_momentum);
  return h.value();
}

StateHash globalStateHash(const particles::ParticleStorage& storage,
                          const particles::ContactHistory& history, MPI_Comm comm) {
  const int rank = mpi::rank(comm);
  std::vector<Keyed> local;
  for (std::size_t i = 0; i < storage.localCount(); ++i) {
    const auto& p = storage[i];
    if (p.isGlobal() && rank != 0) continue;  // replicated: count rank 0's copy only
    local.push_back({p.uid, 0, particleHash(p)});
  }
  std::vector<Keyed> pairs;
  const auto keys = history.keys();
  const auto entries = history.entries();
  particles::ContactHistory::Cursor cursor(history);
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const auto [sub_keys, subs] = cursor.subs(keys[k]);
    pairs.push_back({keys[k].lo, keys[k].hi, historyHash(keys[k], entries[k], sub_keys, subs)});
  }
  auto all_particles = mpi::gatherv(local, 0, comm);
  auto all_pairs = mpi::gatherv(pairs, 0, comm);

  std::uint64_t out[6] = {0, 0, 0, 0, 0, 0};
  if (rank == 0) {
    std::sort(all_particles.begin(), all_particles.end());
    BitHasher ph;
    for (const auto& k : all_particles) {
      ph.add(static_cast<std::uint64_t>(k.a));
      ph.add(k.hash);
    }
    std::sort(all_pairs.begin(), all_pairs.end());
    BitHasher hh;
    std::int64_t unique = 0, conflicts = 0;
    for (std::size_t i = 0; i < all_pairs.size(); ++i) {
      const auto& k = all_pairs[i];
      if (i > 0 && all_pairs[i - 1].a == k.a && all_pairs[i - 1].b == k.b) {
        if (all_pairs[i - 1].hash != k.hash) ++conflicts;
        continue;  // the same pair held by two ranks
      }
      ++unique;
      hh.add(static_cast<std::uint64_t>(k.a));
      hh.add(static_cast<std::uint64_t>(k.b));
      hh.add(k.hash);
    }
    BitHasher all;
    all.add(ph.value());
    all.add(hh.value());
    out[0] = ph.value();
    out[1] = hh.value();
    out[2] = all.value();
    out[3] = all_particles.size();
    out[4] = static_cast<std::uint64_t>(unique);
    out[5] = static_cast<std::uint64_t>(conflicts);
  }
  MPI_Bcast(out, 6, MPI_UINT64_T, 0, comm);
  return {out[0],
          out[1],
          out[2],
          static_cast<std::int64_t>(out[3]),
          static_cast<std::int64_t>(out[4]),
          static_cast<std::int64_t>(out[5])};
}

}  // namespace polydem::comm

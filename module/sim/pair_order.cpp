#include "polydem/sim/pair_order.h"

#include <algorithm>

#include "polydem/core/memory.h"

namespace polydem::sim {

namespace {

// Turns the counts in `start` (one more entry than there are ranks) into the first slot of each
// rank: the fill pointers of a stable counting sort.
void toStarts(std::vector<std::size_t>& start) {
  std::size_t sum = 0;
  for (std::size_t& s : start) {
    const std::size_t count = s;
    s = sum;
    sum += count;
  }
}

// The pairs of one key (periodic images of one pair) by storage indices (a, b): they arrive in
// broad-phase order, next to each other, and are few.
void sortImages(std::vector<OrderedPair>& pairs) {
  for (std::size_t k = 1; k < pairs.size(); ++k) {
    if (!(pairs[k].key == pairs[k - 1].key)) continue;
    const OrderedPair c = pairs[k];
    std::size_t j = k;
    for (; j > 0 && pairs[j - 1].key == c.key &&
           (c.a != pairs[j - 1].a ? c.a < pairs[j - 1].a : c.b < pairs[j - 1].b);
         --j) {
      pairs[j] = pairs[j - 1];
    }
    pairs[j] = c;
  }
}

}  // namespace

// Key order (lo uid, hi uid, a, b) without comparing pairs: the particles are ranked by uid (one
// sort of the storage, a few times smaller than the pairs), and the pairs are put in order by two
// counting sorts (a radix sort with the ranks as digits): by the rank of the higher uid, then,
// stably, by the rank of the lower uid. That leaves only the pairs of one key (periodic images)
// to order by storage indices. The order is the same as a comparison sort's: the keys are unique
// but for those images, and they are ordered by (a, b).
std::span<const OrderedPair> PairOrder::sort(
    const particles::ParticleStorage& storage,
    std::span<const broadphase::CandidatePair> candidates) {
  const std::size_t n = storage.size();
  by_uid_.resize(n);
  for (std::size_t i = 0; i < n; ++i) by_uid_[i] = {storage[i].uid, static_cast<std::int32_t>(i)};
  std::sort(by_uid_.begin(), by_uid_.end());
  uid_rank_.resize(n);
  std::int32_t rank = -1;
  for (std::size_t k = 0; k < n; ++k) {
    if (k == 0 || by_uid_[k].first != by_uid_[k - 1].first) ++rank;  // images share a rank
    uid_rank_[by_uid_[k].second] = rank;
  }
  // Each candidate in canonical form (A the lower uid), counted by both ranks.
  auto canonical = [&](const broadphase::CandidatePair& c) {
    return storage[c.i].uid < storage[c.j].uid ? broadphase::CandidatePair{c.i, c.j}
                                               : broadphase::CandidatePair{c.j, c.i};
  };
  lo_start_.assign(static_cast<std::size_t>(rank) + 1, 0);
  hi_start_.assign(static_cast<std::size_t>(rank) + 1, 0);
  for (const auto& c : candidates) {
    const auto x = canonical(c);
    ++lo_start_[uid_rank_[x.i]];
    ++hi_start_[uid_rank_[x.j]];
  }
  // Grown by a quarter, not doubled (core/memory.h reserveFor): kept for the whole run.
  reserveFor(by_hi_, candidates.size());
  reserveFor(canonical_, candidates.size());
  by_hi_.resize(candidates.size());
  canonical_.resize(candidates.size());
  // First by the rank of B, as storage indices alone; then, stably, by the rank of A into the
  // ordered pairs, keys included.
  toStarts(hi_start_);
  for (const auto& c : candidates) {
    const auto x = canonical(c);
    by_hi_[hi_start_[uid_rank_[x.j]]++] = x;
  }
  toStarts(lo_start_);
  for (const auto& x : by_hi_) {
    canonical_[lo_start_[uid_rank_[x.i]]++] =
        OrderedPair{{storage[x.i].uid, storage[x.j].uid}, x.i, x.j};
  }
  sortImages(canonical_);
  return canonical_;
}

std::uint64_t PairOrder::heapBytes() const {
  return capacityBytes(canonical_) + capacityBytes(by_hi_) + capacityBytes(by_uid_) +
         capacityBytes(uid_rank_) + capacityBytes(lo_start_) + capacityBytes(hi_start_);
}

}  // namespace polydem::sim

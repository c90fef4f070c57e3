#include "polydem/sim/pair_order.h"

#include <algorithm>

#include "polydem/core/memory.h"

namespace polydem::sim {

namespace {

// Counting sort of `in` into `out` by rank(pair) (stable): `start` holds one more entry than there
// are ranks and is used up as the fill pointers.
template <typename Rank>
void scatter(std::span<const OrderedPair> in, std::vector<std::size_t>& start,
             std::vector<OrderedPair>& out, Rank rank) {
  std::size_t sum = 0;
  for (std::size_t& s : start) {
    const std::size_t count = s;
    s = sum;
    sum += count;
  }
  for (const OrderedPair& x : in) out[start[rank(x)]++] = x;
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
  // Each candidate in canonical form, counted by both ranks.
  lo_start_.assign(static_cast<std::size_t>(rank) + 1, 0);
  hi_start_.assign(static_cast<std::size_t>(rank) + 1, 0);
  // Grown by a quarter, not doubled (core/memory.h reserveFor): kept for the whole run.
  reserveFor(canonical_, candidates.size());
  reserveFor(by_hi_, candidates.size());
  canonical_.resize(candidates.size());
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    const auto& c = candidates[k];
    const Uid ui = storage[c.i].uid, uj = storage[c.j].uid;
    const OrderedPair x =
        ui < uj ? OrderedPair{{ui, uj}, c.i, c.j} : OrderedPair{{uj, ui}, c.j, c.i};
    canonical_[k] = x;
    ++lo_start_[uid_rank_[x.a]];
    ++hi_start_[uid_rank_[x.b]];
  }
  by_hi_.resize(candidates.size());
  // The second sort writes back into canonical_, whose broad-phase order is no longer needed.
  scatter(canonical_, hi_start_, by_hi_, [&](const OrderedPair& x) { return uid_rank_[x.b]; });
  scatter(by_hi_, lo_start_, canonical_, [&](const OrderedPair& x) { return uid_rank_[x.a]; });
  sortImages(canonical_);
  return canonical_;
}

std::uint64_t PairOrder::heapBytes() const {
  return capacityBytes(canonical_) + capacityBytes(by_hi_) + capacityBytes(by_uid_) +
         capacityBytes(uid_rank_) + capacityBytes(lo_start_) + capacityBytes(hi_start_);
}

}  // namespace polydem::sim

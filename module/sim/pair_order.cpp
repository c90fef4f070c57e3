#include "polydem/sim/pair_order.h"

#include <algorithm>

namespace polydem::sim {

namespace {

// Pairs of one lower uid ordered by (higher uid, a, b): insertion sort, as the few pairs of one
// particle come nearly ordered from the broad phase.
void sortBucket(OrderedPair* first, OrderedPair* last) {
  auto less = [](const OrderedPair& x, const OrderedPair& y) {
    return x.key.hi != y.key.hi ? x.key.hi < y.key.hi : (x.a != y.a ? x.a < y.a : x.b < y.b);
  };
  for (OrderedPair* i = first + 1; i < last; ++i) {
    const OrderedPair c = *i;
    OrderedPair* j = i;
    for (; j > first && less(c, *(j - 1)); --j) *j = *(j - 1);
    *j = c;
  }
}

}  // namespace

// Key order (lo uid, hi uid, a, b) without comparing pairs: the particles are ranked by uid (one
// sort of the storage, a few times smaller than the pairs), the pairs are bucketed by the rank of
// their lower uid (a counting sort) and each bucket is sorted on its own.
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
  bucket_start_.assign(static_cast<std::size_t>(rank) + 2, 0);
  for (const auto& c : candidates) {
    const std::int32_t lo = storage[c.i].uid < storage[c.j].uid ? c.i : c.j;
    ++bucket_start_[uid_rank_[lo] + 1];
  }
  for (std::size_t b = 1; b < bucket_start_.size(); ++b) bucket_start_[b] += bucket_start_[b - 1];
  pairs_.resize(candidates.size());
  fill_ = bucket_start_;
  for (const auto& c : candidates) {
    const Uid ui = storage[c.i].uid, uj = storage[c.j].uid;
    const OrderedPair x =
        ui < uj ? OrderedPair{{ui, uj}, c.i, c.j} : OrderedPair{{uj, ui}, c.j, c.i};
    pairs_[fill_[uid_rank_[x.a]]++] = x;
  }
  for (std::size_t b = 0; b + 1 < bucket_start_.size(); ++b) {
    sortBucket(pairs_.data() + bucket_start_[b], pairs_.data() + bucket_start_[b + 1]);
  }
  return pairs_;
}

}  // namespace polydem::sim

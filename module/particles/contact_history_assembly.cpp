// ContactHistory's one-pass assembly: a table built from records that come in rounds (a restart
// reads a checkpoint's histories in bounded chunks and routes each to the owners).
//
// Merging every round into the sorted table walks the whole table per round, so n records in r
// rounds cost O(n r). Here each round is only sorted by itself (one copy of each key kept) and
// appended to the end of the table's own arrays, grown by a quarter; a sub-contact keeps the
// index of its pair (4 bytes) instead of its pair's key, found in its own round, else among the
// earlier rounds' pairs, which are sorted for that (a checkpoint's reader hands out every pair
// before any sub-contact, so this happens once). endAssembly orders 4-byte indices (the pairs
// by key; the sub-contacts counted into their pairs' blocks, each block by feature) and applies
// the permutation in place, cycle by cycle, each entry moved once: O(n log n) in all, and beside
// the table only 4 bytes per sub-contact (its pair) and, while sorting, 4 to 8 bytes per entry.
//
// Equal keys are ordered by where they lie, that is by arrival (the rounds in order, within a
// round its sorted order), and the first is kept: the copy merge keeps, so the table's bits are
// those of merging the rounds one by one.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <numeric>
#include <utility>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/particles/contact_history.h"
#include "polydem/particles/contact_history_records.h"

namespace polydem::particles {

namespace {

constexpr std::size_t kMaxIndex = std::numeric_limits<std::uint32_t>::max();
constexpr std::uint32_t kNotHere = std::numeric_limits<std::uint32_t>::max();  // not in the round

// 0, 1, ..., n - 1 ordered by `less` on indices, equal elements by index (arrival).
template <typename Less>
std::vector<std::uint32_t> orderOf(std::size_t n, Less less) {
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), std::uint32_t{0});
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    if (less(a, b)) return true;
    return !less(b, a) && a < b;
  });
  return order;
}

}  // namespace

void ContactHistory::beginAssembly() {
  if (rebuilding_ || open_ > 0) refuse("beginAssembly: during a rebuild");
  clear();
  assembling_ = true;
}

void ContactHistory::appendRecords(HistoryRecords records) {
  if (!assembling_) refuse("appendRecords: no assembly begun");
  if (records.keys.size() != records.entries.size() ||
      records.sub_keys.size() != records.sub_entries.size()) {
    refuse("appendRecords: keys and entries of different counts");
  }
  detail::sortUnique(records.keys, records.entries);
  detail::sortUnique(records.sub_keys, records.sub_entries);
  if (pairs_ + records.keys.size() >= kMaxIndex || subs_ + records.sub_keys.size() > kMaxIndex) {
    clear();
    throw Error(
        cat("ContactHistory: more than ", kMaxIndex, " pair or sub-contact histories on one rank"));
  }
  // Every sub-contact's pair, before anything is appended: in this round (the round's pairs go
  // to [pairs_, pairs_ + n)), else among the earlier rounds' pairs, sorted first if need be (so
  // that no index found moves).
  std::vector<std::uint32_t> pair_of(records.sub_keys.size(), kNotHere);
  bool earlier = false;
  for (std::size_t s = 0, r = 0; s < records.sub_keys.size(); ++s) {
    const PairKey& pair = records.sub_keys[s].pair;
    while (r < records.keys.size() && records.keys[r] < pair) ++r;
    if (r < records.keys.size() && records.keys[r] == pair) {
      pair_of[s] = static_cast<std::uint32_t>(r);
    } else {
      earlier = true;
    }
  }
  if (earlier && sorted_pairs_ < pairs_) sortAssembledPairs();  // before any index is taken
  for (std::size_t s = 0; s < pair_of.size(); ++s) {
    pair_of[s] = pair_of[s] == kNotHere ? assembledPair(records.sub_keys[s].pair)
                                        : static_cast<std::uint32_t>(pairs_ + pair_of[s]);
  }
  const std::size_t pairs = pairs_ + records.keys.size(), subs = subs_ + records.sub_keys.size();
  detail::growRoom(keys_, pairs_, pairs);
  detail::growRoom(entries_, pairs_, pairs);
  std::copy(records.keys.begin(), records.keys.end(), keys_.begin() + pairs_);
  std::copy(records.entries.begin(), records.entries.end(), entries_.begin() + pairs_);
  detail::growRoom(sub_keys_, subs_, subs);
  detail::growRoom(sub_entries_, subs_, subs);
  detail::growRoom(sub_pair_, subs_, subs);
  for (std::size_t s = 0; s < records.sub_keys.size(); ++s) {
    sub_keys_[subs_ + s].feature = records.sub_keys[s].feature;
  }
  std::copy(records.sub_entries.begin(), records.sub_entries.end(), sub_entries_.begin() + subs_);
  std::copy(pair_of.begin(), pair_of.end(), sub_pair_.begin() + subs_);
  pairs_ = pairs;
  subs_ = subs;
}

void ContactHistory::endAssembly() {
  if (!assembling_) refuse("endAssembly: no assembly begun");
  if (sorted_pairs_ < pairs_) sortAssembledPairs();
  sortAssembledSubs();
  assembling_ = false;
  sorted_pairs_ = 0;
  std::vector<std::uint32_t>().swap(sub_pair_);
  dropOld();
}

std::uint32_t ContactHistory::assembledPair(const PairKey& key) {
  if (sorted_pairs_ < pairs_) sortAssembledPairs();
  const auto end = keys_.begin() + static_cast<std::ptrdiff_t>(pairs_);
  const auto it = std::lower_bound(keys_.begin(), end, key);
  if (it != end && *it == key) return static_cast<std::uint32_t>(it - keys_.begin());
  clear();
  refuseOrphan(key);
}

// The pairs sorted by key (equal keys by arrival), each sub-contact's pair index taken to where
// the first copy of its pair goes, the pairs permuted in place and the later copies dropped.
void ContactHistory::sortAssembledPairs() {
  std::vector<std::uint32_t> order =
      orderOf(pairs_, [&](std::uint32_t a, std::uint32_t b) { return keys_[a] < keys_[b]; });
  {
    std::vector<std::uint32_t> where(pairs_);
    std::uint32_t kept = 0;
    for (std::size_t i = 0; i < pairs_; ++i) {
      const bool copy = i > 0 && keys_[order[i]] == keys_[order[i - 1]];
      where[order[i]] = copy ? kept - 1 : kept++;
    }
    for (std::size_t s = 0; s < subs_; ++s) sub_pair_[s] = where[sub_pair_[s]];
  }
  detail::permuteInPlace(order, keys_, entries_);
  std::size_t kept = 0;
  for (std::size_t i = 0; i < pairs_; ++i) {
    if (kept > 0 && keys_[kept - 1] == keys_[i]) continue;
    keys_[kept] = keys_[i];
    entries_[kept++] = entries_[i];
  }
  pairs_ = sorted_pairs_ = kept;
}

// The sub-contacts ordered by pair (counted into the pairs' blocks, sub_end_ holding the
// counts, then the block starts, then the ends), each block by feature (equal ones by arrival),
// permuted in place, the later copies dropped.
void ContactHistory::sortAssembledSubs() {
  detail::growRoom(sub_end_, 0, pairs_);
  std::fill_n(sub_end_.begin(), pairs_, std::size_t{0});
  for (std::size_t s = 0; s < subs_; ++s) ++sub_end_[sub_pair_[s]];
  for (std::size_t p = 0, start = 0; p < pairs_; ++p) start += std::exchange(sub_end_[p], start);
  std::vector<std::uint32_t> order(subs_);
  for (std::uint32_t s = 0; s < subs_; ++s) order[sub_end_[sub_pair_[s]]++] = s;
  const auto by_feature = [&](std::uint32_t a, std::uint32_t b) {
    return sub_keys_[a].feature < sub_keys_[b].feature ||
           (sub_keys_[a].feature == sub_keys_[b].feature && a < b);
  };
  for (std::size_t p = 0; p < pairs_; ++p) {
    std::sort(order.begin() + static_cast<std::ptrdiff_t>(subBegin(p)),
              order.begin() + static_cast<std::ptrdiff_t>(sub_end_[p]), by_feature);
  }
  detail::permuteInPlace(order, sub_keys_, sub_entries_);
  std::vector<std::uint32_t>().swap(order);
  std::size_t kept = 0;
  for (std::size_t p = 0, s = 0; p < pairs_; ++p) {
    const std::size_t first = kept;
    for (; s < sub_end_[p]; ++s) {
      if (kept > first && sub_keys_[kept - 1] == sub_keys_[s]) continue;
      sub_keys_[kept] = sub_keys_[s];
      sub_entries_[kept++] = sub_entries_[s];
    }
    sub_end_[p] = kept;
  }
  subs_ = kept;
}

}  // namespace polydem::particles

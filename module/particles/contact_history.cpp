#include "polydem/particles/contact_history.h"

#include <algorithm>
#include <numeric>

#include "polydem/core/error.h"
#include "polydem/core/memory.h"
#include "polydem/core/strings.h"

namespace polydem::particles {

namespace {

// Sorts (keys, entries) by key into `out_keys`, `out_entries`, keeping the first of equal keys.
template <typename Key, typename Entry>
void mergeTable(std::vector<Key>& out_keys, std::vector<Entry>& out_entries,
                std::span<const Key> keys, std::span<const Entry> entries) {
  std::vector<Key> all_keys(out_keys);
  std::vector<Entry> all_entries(out_entries);
  all_keys.insert(all_keys.end(), keys.begin(), keys.end());
  all_entries.insert(all_entries.end(), entries.begin(), entries.end());
  std::vector<std::size_t> order(all_keys.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return all_keys[a] < all_keys[b]; });
  out_keys.clear();
  out_entries.clear();
  for (std::size_t i : order) {
    if (!out_keys.empty() && out_keys.back() == all_keys[i]) continue;
    out_keys.push_back(all_keys[i]);
    out_entries.push_back(all_entries[i]);
  }
}

}  // namespace

void pack(SendBuffer& out, const PairKey& key, const PairHistory& h) {
  out << key.lo << key.hi << h.shear_force << h.normal << h.kernel.warm_direction
      << h.kernel.warm_point << h.kernel.warm_valid << h.kernel.reserved << h.touching;
}

void unpack(RecvBuffer& in, PairKey& key, PairHistory& h) {
  in >> key.lo >> key.hi >> h.shear_force >> h.normal >> h.kernel.warm_direction >>
      h.kernel.warm_point >> h.kernel.warm_valid >> h.kernel.reserved >> h.touching;
}

void pack(SendBuffer& out, const SubKey& key, const SubHistory& h) {
  out << key.pair.lo << key.pair.hi << key.feature << h.shear_force << h.normal << h.law[0]
      << h.law[1];
}

void unpack(RecvBuffer& in, SubKey& key, SubHistory& h) {
  in >> key.pair.lo >> key.pair.hi >> key.feature >> h.shear_force >> h.normal >> h.law[0] >>
      h.law[1];
}

void ContactHistory::clear() {
  keys_.clear();
  entries_.clear();
  sub_end_.clear();
  subs_ = 0;
  open_ = 0;
}

std::uint64_t ContactHistory::pairBytes() const {
  return capacityBytes(keys_) + capacityBytes(entries_) + capacityBytes(sub_end_);
}

std::uint64_t ContactHistory::subBytes() const {
  return capacityBytes(sub_keys_) + capacityBytes(sub_entries_);
}

const PairHistory* ContactHistory::find(const PairKey& key) const {
  const auto it = std::lower_bound(keys_.begin(), keys_.end(), key);
  if (it == keys_.end() || *it != key) return nullptr;
  return &entries_[static_cast<std::size_t>(it - keys_.begin())];
}

std::pair<std::size_t, std::size_t> ContactHistory::subRange(const PairKey& key) const {
  const auto it = std::lower_bound(keys_.begin(), keys_.end(), key);
  const auto k = static_cast<std::size_t>(it - keys_.begin());
  const std::size_t first = subBegin(k);
  return {first, it == keys_.end() || *it != key ? first : sub_end_[k]};
}

void ContactHistory::appendSubs(const PairKey& pair, std::span<const SubEntry> subs) {
  if (subs.empty()) return;
  if (keys_.empty() || keys_.back() != pair) {
    refuse("appendSubs: sub-contacts of a pair other than the last appended");
  }
  const SubSlots slots = openSubs(subs.size());
  for (std::size_t i = 0; i < subs.size(); ++i) {
    slots.keys[i].feature = subs[i].feature;
    slots.entries[i] = subs[i].history;
  }
  closeSubs(subs.size());
}

void ContactHistory::refuse(const char* what) {
  throw Error(cat("ContactHistory::", what));
}

void ContactHistory::growSubs(std::size_t size) {
  // Grown geometrically: a table that starts without slots (the first steps' tables, the history
  // that Simulation::startLeapfrog restores from a copy) would otherwise grow by one pair's
  // sub-contacts per pair, a reallocation for every pair of the step. By a quarter, not doubled
  // (core/memory.h growthFor): both tables keep their slots for the whole run.
  const std::size_t slots = std::max(size, growthFor(sub_keys_.size()));
  sub_keys_.reserve(slots);
  sub_entries_.reserve(slots);
  sub_keys_.resize(slots);
  sub_entries_.resize(slots);
}

void ContactHistory::growPairs() {
  const std::size_t pairs = growthFor(keys_.size());
  keys_.reserve(pairs);
  entries_.reserve(pairs);
  sub_end_.reserve(pairs);
}

void ContactHistory::indexSubs() {
  sub_end_.assign(keys_.size(), 0);
  std::size_t s = 0;
  for (std::size_t k = 0; k < keys_.size(); ++k) {
    if (s < subs_ && sub_keys_[s].pair < keys_[k]) break;  // no pair entry: below
    while (s < subs_ && sub_keys_[s].pair == keys_[k]) ++s;
    sub_end_[k] = s;
  }
  if (s != subs_) {
    const PairKey& orphan = sub_keys_[s].pair;
    throw Error(cat("ContactHistory: sub-contact history of pair (", orphan.lo, ", ", orphan.hi,
                    ") without the pair's own history (inconsistent data)"));
  }
}

void ContactHistory::merge(std::span<const PairKey> keys, std::span<const PairHistory> entries) {
  mergeTable(keys_, entries_, keys, entries);
  open_ = 0;
  indexSubs();
}

void ContactHistory::merge(const HistoryRecords& records) {
  mergeTable<PairKey, PairHistory>(keys_, entries_, records.keys, records.entries);
  sub_keys_.resize(subs_);  // the slots kept for reuse are not entries
  sub_entries_.resize(subs_);
  mergeTable<SubKey, SubHistory>(sub_keys_, sub_entries_, records.sub_keys, records.sub_entries);
  subs_ = sub_keys_.size();
  open_ = 0;
  indexSubs();
}

void ContactHistory::copyPair(std::size_t pair_index, HistoryRecords& records) const {
  records.keys.push_back(keys_[pair_index]);
  records.entries.push_back(entries_[pair_index]);
  const std::size_t first = subBegin(pair_index), last = sub_end_[pair_index];
  records.sub_keys.insert(records.sub_keys.end(), sub_keys_.begin() + first,
                          sub_keys_.begin() + last);
  records.sub_entries.insert(records.sub_entries.end(), sub_entries_.begin() + first,
                             sub_entries_.begin() + last);
}

}  // namespace polydem::particles

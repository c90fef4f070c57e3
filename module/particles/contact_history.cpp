#include "polydem/particles/contact_history.h"

#include <algorithm>
#include <numeric>

#include "polydem/core/error.h"

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
  out << key.pair.lo << key.pair.hi << key.feature << h.shear_force << h.normal;
}

void unpack(RecvBuffer& in, SubKey& key, SubHistory& h) {
  in >> key.pair.lo >> key.pair.hi >> key.feature >> h.shear_force >> h.normal;
}

void ContactHistory::clear() {
  keys_.clear();
  entries_.clear();
  sub_keys_.clear();
  sub_entries_.clear();
}

const PairHistory* ContactHistory::find(const PairKey& key) const {
  const auto it = std::lower_bound(keys_.begin(), keys_.end(), key);
  if (it == keys_.end() || *it != key) return nullptr;
  return &entries_[static_cast<std::size_t>(it - keys_.begin())];
}

std::pair<std::size_t, std::size_t> ContactHistory::subRange(const PairKey& key) const {
  const auto lo = std::lower_bound(sub_keys_.begin(), sub_keys_.end(), SubKey{key, 0});
  auto hi = lo;
  while (hi != sub_keys_.end() && hi->pair == key) ++hi;
  return {static_cast<std::size_t>(lo - sub_keys_.begin()),
          static_cast<std::size_t>(hi - sub_keys_.begin())};
}

void ContactHistory::appendSorted(const PairKey& key, const PairHistory& h) {
  if (!keys_.empty() && !(keys_.back() < key)) {
    throw Error("ContactHistory::appendSorted: keys must be strictly increasing");
  }
  keys_.push_back(key);
  entries_.push_back(h);
}

void ContactHistory::appendSubs(const PairKey& pair, std::span<const SubEntry> subs) {
  if (subs.empty()) return;
  bool increasing = sub_keys_.empty() || sub_keys_.back() < SubKey{pair, subs.front().feature};
  for (std::size_t i = 1; i < subs.size(); ++i) {
    increasing = increasing && subs[i - 1].feature < subs[i].feature;
  }
  if (!increasing) throw Error("ContactHistory::appendSubs: keys must be strictly increasing");
  for (const SubEntry& s : subs) {
    sub_keys_.push_back({pair, s.feature});
    sub_entries_.push_back(s.history);
  }
}

void ContactHistory::merge(std::span<const PairKey> keys, std::span<const PairHistory> entries) {
  mergeTable(keys_, entries_, keys, entries);
}

void ContactHistory::merge(const HistoryRecords& records) {
  mergeTable<PairKey, PairHistory>(keys_, entries_, records.keys, records.entries);
  mergeTable<SubKey, SubHistory>(sub_keys_, sub_entries_, records.sub_keys, records.sub_entries);
}

void ContactHistory::copyPair(std::size_t pair_index, HistoryRecords& records) const {
  const PairKey& key = keys_[pair_index];
  records.keys.push_back(key);
  records.entries.push_back(entries_[pair_index]);
  const auto [first, last] = subRange(key);
  records.sub_keys.insert(records.sub_keys.end(), sub_keys_.begin() + first,
                          sub_keys_.begin() + last);
  records.sub_entries.insert(records.sub_entries.end(), sub_entries_.begin() + first,
                             sub_entries_.begin() + last);
}

const PairHistory* ContactHistory::Cursor::seek(const PairKey& key) {
  while (pos_ < h_.keys_.size() && h_.keys_[pos_] < key) ++pos_;
  if (pos_ < h_.keys_.size() && h_.keys_[pos_] == key) return &h_.entries_[pos_];
  return nullptr;
}

std::pair<std::span<const SubKey>, std::span<const SubHistory>> ContactHistory::Cursor::subs(
    const PairKey& key) {
  const auto& k = h_.sub_keys_;
  while (sub_pos_ < k.size() && k[sub_pos_].pair < key) ++sub_pos_;
  std::size_t end = sub_pos_;
  while (end < k.size() && k[end].pair == key) ++end;
  const std::span<const SubKey> keys(k.data() + sub_pos_, end - sub_pos_);
  const std::span<const SubHistory> entries(h_.sub_entries_.data() + sub_pos_, end - sub_pos_);
  return {keys, entries};
}

}  // namespace polydem::particles

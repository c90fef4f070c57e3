#include "particles/contact_history.h"

#include <algorithm>
#include <numeric>

#include "core/error.h"

namespace polydem::particles {

void pack(SendBuffer& out, const PairKey& key, const PairHistory& h) {
  out << key.lo << key.hi << h.shear_force << h.normal << h.kernel.warm_direction
      << h.kernel.warm_point << h.kernel.warm_valid << h.kernel.reserved << h.touching;
}

void unpack(RecvBuffer& in, PairKey& key, PairHistory& h) {
  in >> key.lo >> key.hi >> h.shear_force >> h.normal >> h.kernel.warm_direction >>
      h.kernel.warm_point >> h.kernel.warm_valid >> h.kernel.reserved >> h.touching;
}

void ContactHistory::clear() {
  keys_.clear();
  entries_.clear();
}

const PairHistory* ContactHistory::find(const PairKey& key) const {
  const auto it = std::lower_bound(keys_.begin(), keys_.end(), key);
  if (it == keys_.end() || *it != key) return nullptr;
  return &entries_[static_cast<std::size_t>(it - keys_.begin())];
}

void ContactHistory::appendSorted(const PairKey& key, const PairHistory& h) {
  if (!keys_.empty() && !(keys_.back() < key)) {
    throw Error("ContactHistory::appendSorted: keys must be strictly increasing");
  }
  keys_.push_back(key);
  entries_.push_back(h);
}

void ContactHistory::merge(std::span<const PairKey> keys, std::span<const PairHistory> entries) {
  std::vector<PairKey> all_keys(keys_);
  std::vector<PairHistory> all_entries(entries_);
  all_keys.insert(all_keys.end(), keys.begin(), keys.end());
  all_entries.insert(all_entries.end(), entries.begin(), entries.end());
  std::vector<std::size_t> order(all_keys.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return all_keys[a] < all_keys[b]; });
  keys_.clear();
  entries_.clear();
  for (std::size_t i : order) {
    if (!keys_.empty() && keys_.back() == all_keys[i]) continue;
    keys_.push_back(all_keys[i]);
    entries_.push_back(all_entries[i]);
  }
}

const PairHistory* ContactHistory::Cursor::seek(const PairKey& key) {
  while (pos_ < h_.keys_.size() && h_.keys_[pos_] < key) ++pos_;
  if (pos_ < h_.keys_.size() && h_.keys_[pos_] == key) return &h_.entries_[pos_];
  return nullptr;
}

}  // namespace polydem::particles

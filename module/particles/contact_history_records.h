// Steps shared by the ways a contact history takes records in any order (ContactHistory::merge
// and the restart's one-pass assembly): a round's records sorted with one copy of each key, and
// the table's room grown by a quarter.
#pragma once

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <tuple>
#include <vector>

#include "polydem/core/memory.h"

namespace polydem::particles::detail {

/// (keys, entries) sorted by key, stable, keeping the first of equal keys.
template <typename Key, typename Entry>
void sortUnique(std::vector<Key>& keys, std::vector<Entry>& entries) {
  std::vector<std::size_t> order(keys.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return keys[a] < keys[b]; });
  std::vector<Key> sorted_keys;
  std::vector<Entry> sorted_entries;
  sorted_keys.reserve(keys.size());
  sorted_entries.reserve(keys.size());
  for (std::size_t i : order) {
    if (!sorted_keys.empty() && sorted_keys.back() == keys[i]) continue;
    sorted_keys.push_back(keys[i]);
    sorted_entries.push_back(entries[i]);
  }
  keys.swap(sorted_keys);
  entries.swap(sorted_entries);
}

/// Room for `needed` slots, [0, front) kept: a new array of a quarter more (core/memory.h
/// growthFor) when it must grow.
template <typename T>
void growRoom(std::vector<T>& v, std::size_t front, std::size_t needed) {
  if (needed <= v.size()) return;
  std::vector<T> out(growthFor(needed));
  std::copy_n(v.begin(), front, out.begin());
  v.swap(out);
}

/// Applies `order` in place to every array (slot i takes what was at order[i]), cycle by cycle,
/// each element moved once; `order` becomes the identity.
template <typename... Arrays>
void permuteInPlace(std::vector<std::uint32_t>& order, Arrays&... arrays) {
  for (std::uint32_t i = 0; i < order.size(); ++i) {
    if (order[i] == i) continue;
    auto held = std::make_tuple(arrays[i]...);
    std::uint32_t j = i;
    for (;;) {
      const std::uint32_t k = order[j];
      order[j] = j;
      if (k == i) break;
      ((arrays[j] = arrays[k]), ...);
      j = k;
    }
    std::apply([&](const auto&... values) { ((arrays[j] = values), ...); }, held);
  }
}

}  // namespace polydem::particles::detail

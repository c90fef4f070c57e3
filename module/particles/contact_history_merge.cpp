// ContactHistory::merge: records in any order merged into the sorted table in place.
//
// The records are sorted once (a copy of the records only, which a caller keeps small: the
// histories arriving with migrated particles), then merged into the table from its end, the way
// two sorted runs merge into the room behind the longer one: an entry of the table moves at most
// once per merge, only if a record sorts below it, and no second copy of the table is held. Each
// merge walks the whole table, so a table built from many rounds of records is assembled in one
// pass instead (contact_history_assembly.cpp). The room grows to the exact size it needs (a
// quarter more: core/memory.h growthFor), one array at a time.
#include <algorithm>
#include <utility>

#include "polydem/core/error.h"
#include "polydem/core/memory.h"
#include "polydem/core/strings.h"
#include "polydem/particles/contact_history.h"
#include "polydem/particles/contact_history_records.h"

namespace polydem::particles {

using detail::growRoom;
using detail::sortUnique;

void ContactHistory::merge(std::span<const PairKey> keys, std::span<const PairHistory> entries) {
  HistoryRecords records;
  records.keys.assign(keys.begin(), keys.end());
  records.entries.assign(entries.begin(), entries.end());
  merge(std::move(records));
}

void ContactHistory::merge(HistoryRecords records) {
  if (rebuilding_ || open_ > 0 || assembling_) refuse("merge: during a rebuild or an assembly");
  if (records.keys.size() != records.entries.size() ||
      records.sub_keys.size() != records.sub_entries.size()) {
    refuse("merge: keys and entries of different counts");
  }
  sortUnique(records.keys, records.entries);
  sortUnique(records.sub_keys, records.sub_entries);
  // Counted before anything moves, so that an orphan leaves the table as it was.
  std::size_t new_pairs = 0, new_subs = 0;
  std::size_t t = 0, r = 0;  // walks over the table's pairs and the records' pairs
  for (const PairKey& key : records.keys) {
    while (t < pairs_ && keys_[t] < key) ++t;
    new_pairs += !(t < pairs_ && keys_[t] == key);
  }
  t = 0;
  for (const SubKey& sub : records.sub_keys) {
    while (t < pairs_ && keys_[t] < sub.pair) ++t;
    while (r < records.keys.size() && records.keys[r] < sub.pair) ++r;
    if (t < pairs_ && keys_[t] == sub.pair) {
      const auto first = sub_keys_.begin() + static_cast<std::ptrdiff_t>(subBegin(t));
      const auto last = sub_keys_.begin() + static_cast<std::ptrdiff_t>(sub_end_[t]);
      new_subs += !std::binary_search(first, last, SubFeature{sub.feature});
    } else if (r < records.keys.size() && records.keys[r] == sub.pair) {
      ++new_subs;
    } else {
      refuseOrphan(sub.pair);
    }
  }
  mergePairs(records, new_pairs);
  mergeSubs(records, new_subs);
  dropOld();
}

// From the end: slot d - 1 takes the larger of the table's last unplaced pair (i - 1) and the
// records' (j - 1); d - 1 >= i - 1, so nothing unplaced is overwritten. sub_end_ becomes each
// pair's sub-contact count (a table pair's block end and the one before it are read before
// either is overwritten). Once every record is placed (d == i), the pairs below are where they
// were: only their counts are taken, nothing moves.
void ContactHistory::mergePairs(const HistoryRecords& sorted, std::size_t added) {
  const std::size_t size = pairs_ + added;
  growRoom(keys_, pairs_, size);
  growRoom(entries_, pairs_, size);
  growRoom(sub_end_, pairs_, size);
  std::size_t i = pairs_, j = sorted.keys.size(), d = size;
  while (i > 0 && d > i) {
    if (j > 0 && sorted.keys[j - 1] == keys_[i - 1]) --j;  // the table's copy is kept
    --d;
    if (j > 0 && keys_[i - 1] < sorted.keys[j - 1]) {
      --j;
      keys_[d] = sorted.keys[j];
      entries_[d] = sorted.entries[j];
      sub_end_[d] = 0;
      continue;
    }
    --i;
    const std::size_t count = sub_end_[i] - subBegin(i);
    keys_[d] = keys_[i];
    entries_[d] = entries_[i];
    sub_end_[d] = count;
  }
  // Every table pair placed: the records left are new (below them all). Else (d == i) they are
  // copies of table pairs.
  while (i == 0 && j > 0) {
    --d;
    --j;
    keys_[d] = sorted.keys[j];
    entries_[d] = sorted.entries[j];
    sub_end_[d] = 0;
  }
  for (std::size_t k = i; k-- > 0;) sub_end_[k] -= subBegin(k);  // in place: counts only
  pairs_ = size;
}

// Pair by pair from the last: its old block (its count from mergePairs, ending where the previous
// pair's began) and the records of the same pair merge by feature into the block ending at d; the
// old one ends at or before d, so nothing unplaced is overwritten. Once every record is placed
// (d == src), the blocks below are where they were: only their ends are set again.
void ContactHistory::mergeSubs(const HistoryRecords& sorted, std::size_t added) {
  const std::size_t size = subs_ + added;
  growRoom(sub_keys_, subs_, size);
  growRoom(sub_entries_, subs_, size);
  std::size_t src = subs_, c = sorted.sub_keys.size(), d = size, k = pairs_;
  for (; k > 0 && d > src; --k) {
    const PairKey& key = keys_[k - 1];
    const std::size_t end = d, first = src - sub_end_[k - 1];
    auto record = [&] { return c > 0 && sorted.sub_keys[c - 1].pair == key; };
    while (src > first || record()) {
      if (record() && src > first && sub_keys_[src - 1].feature == sorted.sub_keys[c - 1].feature) {
        --c;  // the table's copy is kept
        continue;
      }
      --d;
      if (record() &&
          (src == first || sub_keys_[src - 1].feature < sorted.sub_keys[c - 1].feature)) {
        --c;
        sub_keys_[d].feature = sorted.sub_keys[c].feature;
        sub_entries_[d] = sorted.sub_entries[c];
      } else {
        --src;
        sub_keys_[d] = sub_keys_[src];
        sub_entries_[d] = sub_entries_[src];
      }
    }
    sub_end_[k - 1] = end;
  }
  std::size_t end = 0;
  for (std::size_t t = 0; t < k; ++t) sub_end_[t] = end += sub_end_[t];  // counts to ends
  subs_ = size;
}

}  // namespace polydem::particles

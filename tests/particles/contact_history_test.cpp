// The contact history's tables (particles/contact_history.h): a pair's sub-contacts are found by
// the pair's own index (its block end), whichever way the tables were filled (appended in key
// order by the contact phase, merged from records in any order), and the table refuses input that
// would break the index.
#include "polydem/particles/contact_history.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "polydem/core/error.h"

namespace polydem::particles {
namespace {

// A history of `pairs` pairs (uids drawn from a small range), each with 0-5 sub-contacts, as
// records in key order.
HistoryRecords randomRecords(std::mt19937_64& rng, int pairs) {
  std::vector<PairKey> keys;
  std::uniform_int_distribution<Uid> uid(1, 60);
  while (static_cast<int>(keys.size()) < pairs) {
    const Uid a = uid(rng), b = uid(rng);
    if (a != b) keys.push_back(makeKey(a, b));
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  HistoryRecords r;
  std::uniform_int_distribution<int> count(0, 5);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  for (const PairKey& k : keys) {
    PairHistory h;
    h.shear_force = Vec3(value(rng), value(rng), value(rng));
    h.touching = 1;
    r.keys.push_back(k);
    r.entries.push_back(h);
    std::uint64_t feature = 0;
    for (int s = count(rng); s > 0; --s) {
      feature += 1 + rng() % 1000;
      r.sub_keys.push_back({k, feature});
      r.sub_entries.push_back({Vec3(value(rng), value(rng), value(rng)), Vec3::UnitZ()});
    }
  }
  return r;
}

// The sub-contacts of `key` in `r`, by a full scan.
std::vector<std::size_t> subsOf(const HistoryRecords& r, const PairKey& key) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < r.sub_keys.size(); ++i) {
    if (r.sub_keys[i].pair == key) out.push_back(i);
  }
  return out;
}

// Every pair's block, through the cursor (alone, after seek, for absent keys) and subRange,
// against a full scan of the records the table was built from.
void expectBlocks(const ContactHistory& h, const HistoryRecords& r) {
  ASSERT_EQ(h.size(), r.keys.size());
  ASSERT_EQ(h.subCount(), r.sub_keys.size());
  ContactHistory::Cursor alone(h), seeking(h);
  for (std::size_t k = 0; k < r.keys.size(); ++k) {
    const PairKey& key = r.keys[k];
    const PairKey absent{key.lo, key.hi - 1};  // below key; maybe a pair of the table
    const bool is_pair = std::binary_search(r.keys.begin(), r.keys.end(), absent);
    if (!is_pair && absent.lo < absent.hi) {
      EXPECT_TRUE(seeking.subs(absent).first.empty());
      const auto [first, last] = h.subRange(absent);
      EXPECT_EQ(first, last);
    }
    ASSERT_NE(seeking.seek(key), nullptr);
    const auto expected = subsOf(r, key);
    for (auto cursor : {&alone, &seeking}) {
      const auto [keys, entries] = cursor->subs(key);
      ASSERT_EQ(keys.size(), expected.size());
      ASSERT_EQ(entries.size(), expected.size());
      for (std::size_t s = 0; s < expected.size(); ++s) {
        EXPECT_EQ(keys[s].feature, r.sub_keys[expected[s]].feature);
        EXPECT_EQ(entries[s].shear_force, r.sub_entries[expected[s]].shear_force);
      }
    }
    const auto [first, last] = h.subRange(key);
    ASSERT_EQ(last - first, expected.size());
    if (!expected.empty()) {
      EXPECT_EQ(h.subFeatures()[first].feature, r.sub_keys[expected.front()].feature);
    }
    HistoryRecords copy;
    h.copyPair(k, copy);
    EXPECT_EQ(copy.keys.front(), key);
    ASSERT_EQ(copy.sub_keys.size(), expected.size());
    for (std::size_t s = 0; s < expected.size(); ++s)
      EXPECT_EQ(copy.sub_keys[s], r.sub_keys[expected[s]]);
  }
}

TEST(ContactHistory, AppendedBlocksAreFoundByPair) {
  std::mt19937_64 rng(15);
  for (int trial = 0; trial < 20; ++trial) {
    const HistoryRecords r = randomRecords(rng, 1 + trial * 10);
    ContactHistory h;
    std::size_t s = 0;
    for (std::size_t k = 0; k < r.keys.size(); ++k) {
      h.appendSorted(r.keys[k], r.entries[k]);
      std::size_t n = 0;
      while (s + n < r.sub_keys.size() && r.sub_keys[s + n].pair == r.keys[k]) ++n;
      // Room for more than are kept, as the law opens one slot per sub-contact it is given.
      const SubSlots slots = h.openSubs(n + trial % 3);
      for (std::size_t i = 0; i < n; ++i) {
        slots.keys[i].feature = r.sub_keys[s + i].feature;
        slots.entries[i] = r.sub_entries[s + i];
      }
      h.closeSubs(n);
      s += n;
    }
    expectBlocks(h, r);
  }
}

TEST(ContactHistory, MergedBlocksAreFoundByPair) {
  std::mt19937_64 rng(16);
  for (int trial = 0; trial < 20; ++trial) {
    const HistoryRecords all = randomRecords(rng, 1 + trial * 10);
    // Two halves: one appended, the other merged in shuffled (as received from other ranks).
    HistoryRecords first, second;
    std::size_t s = 0;
    for (std::size_t k = 0; k < all.keys.size(); ++k) {
      HistoryRecords& to = k % 2 ? second : first;
      to.keys.push_back(all.keys[k]);
      to.entries.push_back(all.entries[k]);
      for (; s < all.sub_keys.size() && all.sub_keys[s].pair == all.keys[k]; ++s) {
        to.sub_keys.push_back(all.sub_keys[s]);
        to.sub_entries.push_back(all.sub_entries[s]);
      }
    }
    ContactHistory h;
    h.merge(first);
    std::vector<std::size_t> order(second.sub_keys.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::shuffle(order.begin(), order.end(), rng);
    HistoryRecords shuffled;
    shuffled.keys.assign(second.keys.rbegin(), second.keys.rend());
    shuffled.entries.assign(second.entries.rbegin(), second.entries.rend());
    for (std::size_t i : order) {
      shuffled.sub_keys.push_back(second.sub_keys[i]);
      shuffled.sub_entries.push_back(second.sub_entries[i]);
    }
    h.merge(shuffled);
    h.merge(shuffled);  // copies from two ranks: one kept
    expectBlocks(h, all);
    // A pair-only merge keeps the sub-contacts with their pairs.
    h.merge(std::span<const PairKey>(), std::span<const PairHistory>());
    expectBlocks(h, all);
  }
}

// Merged chunk by chunk, as a restart merges a checkpoint's histories: chunks of any size, the
// pairs before the sub-contacts or each pair with its own, some records twice (a pair whose two
// particles a rank owns arrives from both directories), give the table of one merge of all.
TEST(ContactHistory, MergedInChunksIsMergedAtOnce) {
  std::mt19937_64 rng(18);
  for (int trial = 0; trial < 30; ++trial) {
    const HistoryRecords all = randomRecords(rng, 1 + trial * 8);
    // The records in a shuffled order, the pairs first (as a checkpoint's tables are read).
    std::vector<std::size_t> pairs(all.keys.size()), subs(all.sub_keys.size());
    for (std::size_t i = 0; i < pairs.size(); ++i) pairs[i] = i;
    for (std::size_t i = 0; i < subs.size(); ++i) subs[i] = i;
    std::shuffle(pairs.begin(), pairs.end(), rng);
    std::shuffle(subs.begin(), subs.end(), rng);
    std::vector<std::pair<bool, std::size_t>> order;  // (sub-contact?, index)
    for (std::size_t i : pairs) order.push_back({false, i});
    for (std::size_t i : subs) order.push_back({true, i});
    ContactHistory h;
    std::uniform_int_distribution<std::size_t> size(1, 1 + trial);
    for (std::size_t at = 0; at < order.size();) {
      HistoryRecords chunk;
      const std::size_t end = std::min(order.size(), at + size(rng));
      for (; at < end; ++at) {
        const auto [sub, i] = order[at];
        for (int copy = 0; copy < (i % 3 == 0 ? 2 : 1); ++copy) {
          if (sub) {
            chunk.sub_keys.push_back(all.sub_keys[i]);
            chunk.sub_entries.push_back(all.sub_entries[i]);
          } else {
            chunk.keys.push_back(all.keys[i]);
            chunk.entries.push_back(all.entries[i]);
          }
        }
      }
      h.merge(chunk);
    }
    expectBlocks(h, all);
    // Again: everything present already, nothing added.
    const std::size_t subs_before = h.subCount();
    h.merge(all);
    EXPECT_EQ(h.subCount(), subs_before);
    expectBlocks(h, all);
  }
}

// The sub-contacts of `key` in `r`, as a pair's block: its entries, and their count.
void expectOld(const ContactHistory::Found& found, const HistoryRecords& r, const PairKey& key) {
  const auto k = std::lower_bound(r.keys.begin(), r.keys.end(), key) - r.keys.begin();
  const bool had = k < static_cast<std::ptrdiff_t>(r.keys.size()) && r.keys[k] == key;
  ASSERT_EQ(found.pair != nullptr, had);
  if (!had) return;
  EXPECT_EQ(found.pair->shear_force, r.entries[k].shear_force);
  const auto expected = subsOf(r, key);
  ASSERT_EQ(found.sub_keys.size(), expected.size());
  ASSERT_EQ(found.subs.size(), expected.size());
  for (std::size_t s = 0; s < expected.size(); ++s) {
    EXPECT_EQ(found.sub_keys[s].feature, r.sub_keys[expected[s]].feature);
    EXPECT_EQ(found.subs[s].shear_force, r.sub_entries[expected[s]].shear_force);
  }
}

// Rebuilt in place, as the contact phase does it: last step's entries read by takeOld are those
// of the old table, whatever the new one writes in front of them (pairs that appear, pairs with
// more sub-contacts than before, pairs gone, slots opened beyond those kept), and the new table is
// the one appended. Rebuilt twice: from a table at rest and from one left with room by the first.
TEST(ContactHistory, RebuiltInPlaceReadsLastStepsTable) {
  std::mt19937_64 rng(17);
  for (int trial = 0; trial < 40; ++trial) {
    const HistoryRecords a = randomRecords(rng, 1 + trial * 5);
    const HistoryRecords b = randomRecords(rng, 1 + (39 - trial) * 5);
    ContactHistory h;
    h.merge(a);
    for (const auto& [before, after] : {std::pair{&a, &b}, std::pair{&b, &a}}) {
      h.beginRebuild();
      std::size_t s = 0;
      for (std::size_t k = 0; k < after->keys.size(); ++k) {
        const PairKey& key = after->keys[k];
        if (k % 7 == 3) {
          h.skipOld(key);  // an early pair: its old entries are not read
        } else {
          expectOld(h.takeOld(key), *before, key);
        }
        h.appendSorted(key, after->entries[k]);
        std::size_t n = 0;
        while (s + n < after->sub_keys.size() && after->sub_keys[s + n].pair == key) ++n;
        const SubSlots slots = h.openSubs(n + trial % 3);
        for (std::size_t i = 0; i < n; ++i) {
          slots.keys[i].feature = after->sub_keys[s + i].feature;
          slots.entries[i] = after->sub_entries[s + i];
        }
        h.closeSubs(n);
        s += n;
      }
      h.endRebuild();
      expectBlocks(h, *after);
    }
  }
}

TEST(ContactHistory, RefusesInputThatBreaksTheIndex) {
  ContactHistory h;
  EXPECT_THROW(h.openSubs(1), Error);  // no pair yet
  h.appendSorted({1, 2}, {});
  SubSlots slots = h.openSubs(2);
  slots.keys[0].feature = 5;
  slots.keys[1].feature = 5;
  EXPECT_THROW(h.closeSubs(2), Error);  // not strictly increasing: the slots are dropped
  EXPECT_TRUE(h.subCount() == 0);
  EXPECT_THROW(h.closeSubs(1), Error);  // none open
  slots = h.openSubs(2);
  slots.keys[0].feature = 5;
  h.closeSubs(1);
  slots = h.openSubs(1);  // more for the same pair: above the ones it has
  slots.keys[0].feature = 3;
  EXPECT_THROW(h.closeSubs(1), Error);
  EXPECT_EQ(h.subCount(), 1u);  // the failed slots dropped
  slots = h.openSubs(1);
  EXPECT_THROW(h.openSubs(1), Error);  // still open
  slots.keys[0].feature = 6;
  h.closeSubs(1);
  EXPECT_EQ(h.subRange({1, 2}), (std::pair<std::size_t, std::size_t>{0, 2}));
  EXPECT_THROW(h.appendSubs({1, 3}, std::vector<SubEntry>{{1, {}}}), Error);  // not the last pair
  h.appendSorted({1, 3}, {});
  h.appendSubs({1, 3}, std::vector<SubEntry>{{1, {}}, {4, {}}});
  EXPECT_EQ(h.subRange({1, 3}), (std::pair<std::size_t, std::size_t>{2, 4}));

  // A sub-contact whose pair has no entry (an inconsistent checkpoint) is refused by merge.
  HistoryRecords orphan;
  orphan.sub_keys.push_back({{2, 3}, 1});
  orphan.sub_entries.push_back({});
  EXPECT_THROW(h.merge(orphan), Error);
  // ... and leaves the table as it was, also beside records it would have added.
  orphan.keys.push_back({1, 4});
  orphan.entries.push_back({});
  orphan.sub_keys.push_back({{1, 2}, 9});
  orphan.sub_entries.push_back({});
  EXPECT_THROW(h.merge(orphan), Error);
  EXPECT_EQ(h.size(), 2u);
  EXPECT_EQ(h.subCount(), 4u);
  EXPECT_EQ(h.subRange({1, 3}), (std::pair<std::size_t, std::size_t>{2, 4}));
}

}  // namespace
}  // namespace polydem::particles

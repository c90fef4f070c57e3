// The contact history's one-pass assembly (particles/contact_history.h appendRecords): records
// that come in rounds, assembled once at the end, give bit for bit the table that merging the
// same rounds one by one gives (the first copy of a key kept), and a sub-contact whose pair has
// not arrived is refused, with nothing half-built left.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "polydem/core/error.h"
#include "polydem/particles/contact_history.h"

namespace polydem::particles {
namespace {

// One record in a round: a pair's history or a sub-contact's.
struct Item {
  bool sub = false;
  PairKey pair;
  PairHistory entry;
  std::uint64_t feature = 0;
  SubHistory sub_entry;
};

using Rounds = std::vector<HistoryRecords>;

Vec3 randomVec(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  return {value(rng), value(rng), value(rng)};
}

// Pairs of uids 1-40 (some without sub-contacts), each with 0-4 sub-contacts, every field
// random, so that a copy kept instead of another shows.
std::vector<Item> randomItems(std::mt19937_64& rng, int pairs) {
  std::vector<Item> items;
  std::uniform_int_distribution<Uid> uid(1, 40);
  for (int k = 0; k < pairs; ++k) {
    const Uid a = uid(rng), b = uid(rng);
    if (a == b) continue;
    Item pair;
    pair.pair = makeKey(a, b);
    pair.entry.shear_force = randomVec(rng);
    pair.entry.normal = randomVec(rng);
    pair.entry.kernel.warm_point = randomVec(rng);
    pair.entry.touching = static_cast<std::uint32_t>(rng() % 2);
    items.push_back(pair);
    for (int s = static_cast<int>(rng() % 5); s > 0; --s) {
      Item sub{true, pair.pair, {}, rng() % 12, {}};
      sub.sub_entry.shear_force = randomVec(rng);
      sub.sub_entry.law = {randomVec(rng).x(), 0.0};
      items.push_back(sub);
    }
  }
  return items;
}

// The items in rounds of random sizes, each sub-contact in its pair's round or a later one: the
// pairs first (as a checkpoint's reader hands them out) or each pair with its sub-contacts; some
// items twice in a round (a pair whose two particles a rank owns comes from both directories),
// some again in a later round with other values (the copy that arrived first must be kept).
Rounds randomRounds(std::mt19937_64& rng, std::vector<Item> items, bool pairs_first) {
  if (pairs_first) {
    std::stable_partition(items.begin(), items.end(), [](const Item& i) { return !i.sub; });
  }
  const std::size_t n = items.size();
  for (std::size_t i = 0; i < n; i += 3) {
    Item later = items[i];
    later.entry.shear_force = randomVec(rng);
    later.sub_entry.shear_force = randomVec(rng);
    const auto at = i + 1 + rng() % (n - i);
    items.insert(items.begin() + static_cast<std::ptrdiff_t>(std::min(at, items.size())), later);
  }
  Rounds rounds;
  for (std::size_t at = 0; at < items.size();) {
    const std::size_t end = std::min(items.size(), at + 1 + rng() % 9);
    std::vector<Item> round(items.begin() + static_cast<std::ptrdiff_t>(at),
                            items.begin() + static_cast<std::ptrdiff_t>(end));
    if (rng() % 2) round.push_back(round.front());
    std::shuffle(round.begin(), round.end(), rng);
    HistoryRecords r;
    for (const Item& i : round) {
      if (i.sub) {
        r.sub_keys.push_back({i.pair, i.feature});
        r.sub_entries.push_back(i.sub_entry);
      } else {
        r.keys.push_back(i.pair);
        r.entries.push_back(i.entry);
      }
    }
    rounds.push_back(r);
    at = end;
  }
  return rounds;
}

ContactHistory merged(const Rounds& rounds) {
  ContactHistory h;
  for (const HistoryRecords& r : rounds) h.merge(r);
  return h;
}

ContactHistory assembled(const Rounds& rounds) {
  ContactHistory h;
  h.beginAssembly();
  for (const HistoryRecords& r : rounds) h.appendRecords(r);
  h.endAssembly();
  return h;
}

// Every field of every entry, and every pair's block.
void expectSameTable(const ContactHistory& a, const ContactHistory& b) {
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.subCount(), b.subCount());
  for (std::size_t k = 0; k < a.size(); ++k) {
    const PairHistory &x = a.entries()[k], &y = b.entries()[k];
    EXPECT_EQ(a.keys()[k], b.keys()[k]);
    EXPECT_EQ(x.shear_force, y.shear_force);
    EXPECT_EQ(x.normal, y.normal);
    EXPECT_EQ(x.kernel.warm_point, y.kernel.warm_point);
    EXPECT_EQ(x.touching, y.touching);
    EXPECT_EQ(a.subsOf(k), b.subsOf(k));
  }
  for (std::size_t s = 0; s < a.subCount(); ++s) {
    EXPECT_EQ(a.subFeatures()[s], b.subFeatures()[s]);
    EXPECT_EQ(a.subEntries()[s].shear_force, b.subEntries()[s].shear_force);
    EXPECT_EQ(a.subEntries()[s].law, b.subEntries()[s].law);
  }
}

TEST(ContactHistoryAssembly, IsMergedRoundByRound) {
  std::mt19937_64 rng(29);
  for (int trial = 0; trial < 60; ++trial) {
    const auto items = randomItems(rng, 1 + trial * 4);
    const Rounds rounds = randomRounds(rng, items, trial % 2 == 0);
    const ContactHistory want = merged(rounds);
    const ContactHistory got = assembled(rounds);
    EXPECT_FALSE(got.assembling());
    expectSameTable(got, want);
    // Its blocks are found by pair.
    for (std::size_t k = 0; k < got.size(); ++k) {
      EXPECT_EQ(got.subRange(got.keys()[k]), got.subsOf(k));
    }
  }
}

TEST(ContactHistoryAssembly, NothingIsAnEmptyTable) {
  ContactHistory h;
  h.beginAssembly();
  h.appendRecords({});
  h.endAssembly();
  EXPECT_TRUE(h.empty());
  EXPECT_EQ(h.subCount(), 0u);
}

// A sub-contact whose pair is in no round so far (an inconsistent checkpoint) throws the error
// merge throws, and leaves an empty table, ready for another assembly.
TEST(ContactHistoryAssembly, RefusesAnOrphanLeavingNothing) {
  std::mt19937_64 rng(30);
  const Rounds rounds = randomRounds(rng, randomItems(rng, 40), true);
  for (const PairKey orphan : {PairKey{50, 51}, PairKey{0, 1}}) {
    // The orphan in a round of its own after the others, then beside pairs of its round.
    for (bool beside : {false, true}) {
      Rounds bad = rounds;
      HistoryRecords r = beside ? rounds.front() : HistoryRecords{};
      r.sub_keys.push_back({orphan, 3});
      r.sub_entries.push_back({});
      bad.push_back(r);
      EXPECT_THROW(merged(bad), Error);
      ContactHistory h;
      h.beginAssembly();
      for (std::size_t i = 0; i + 1 < bad.size(); ++i) h.appendRecords(bad[i]);
      try {
        h.appendRecords(bad.back());
        ADD_FAILURE() << "an orphan sub-contact was taken";
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("without the pair's own history"), std::string::npos);
      }
      EXPECT_FALSE(h.assembling());
      EXPECT_TRUE(h.empty());
      EXPECT_EQ(h.subCount(), 0u);
      EXPECT_THROW(h.endAssembly(), Error);  // nothing left to end
      h.beginAssembly();
      for (std::size_t i = 0; i + 1 < bad.size(); ++i) h.appendRecords(bad[i]);
      h.endAssembly();
      expectSameTable(h, merged(rounds));
    }
  }
  // A sub-contact before its pair's round: merge refuses it, and so does the assembly.
  Rounds early(2);
  early[0].sub_keys.push_back({{1, 2}, 1});
  early[0].sub_entries.push_back({});
  early[1].keys.push_back({1, 2});
  early[1].entries.push_back({});
  EXPECT_THROW(merged(early), Error);
  EXPECT_THROW(assembled(early), Error);
}

TEST(ContactHistoryAssembly, OtherCallsWaitForItsEnd) {
  ContactHistory h;
  EXPECT_THROW(h.appendRecords({}), Error);
  h.beginAssembly();
  EXPECT_THROW(h.merge(HistoryRecords{}), Error);
  EXPECT_THROW(h.beginRebuild(), Error);
  h.endAssembly();
  h.beginRebuild();
  EXPECT_THROW(h.beginAssembly(), Error);
  h.endRebuild();
}

}  // namespace
}  // namespace polydem::particles

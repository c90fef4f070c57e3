// Contact history: per-pair memory kept between steps, keyed by the ordered uid pair.
//
// It holds the tangential (shear) force, the previous contact normal (to rotate the shear force
// onto the new contact plane, Zhao eqs. 33-34) and the kernel's warm start (previous common plane
// or separating axis). With the sub-contact model (contact/face/face_contact.h) every sub-contact
// of a pair has a shear spring of its own, kept in a second table under its features alone: a
// pair's sub-contacts are one contiguous block, and each pair keeps the end of its block, so the
// pair of a sub-contact is implied by where it lies. Both live outside the kernels so that they can
// migrate with particles and be written to checkpoints.
//
// Both tables are sorted by key. The narrow phase visits candidate pairs in the same key order,
// so it rebuilds the table in place, in one pass (beginRebuild): the new step's entries are
// written from the front while last step's are read ahead of them, so that one copy of the
// history is held, not two. Where the new entries would reach unread old ones (pairs that appear,
// a pair with more sub-contacts than before), the unread rest moves to the end of the table's
// room, which grows by a quarter when that is not enough. A pair whose two particles are owned by
// different ranks is evaluated on both ranks from identical inputs, so both copies stay
// bit-for-bit equal.
#pragma once

#include <algorithm>
#include <array>
#include <span>
#include <utility>
#include <vector>

#include "polydem/core/byte_buffer.h"
#include "polydem/core/types.h"
#include "polydem/particles/pair_state.h"

namespace polydem::particles {

struct PairKey {
  Uid lo = 0, hi = 0;  // lo < hi
  friend bool operator==(const PairKey&, const PairKey&) = default;
  friend auto operator<=>(const PairKey&, const PairKey&) = default;
  bool involves(Uid uid) const { return lo == uid || hi == uid; }
};

inline PairKey makeKey(Uid a, Uid b) {
  return a < b ? PairKey{a, b} : PairKey{b, a};
}

struct PairHistory {
  Vec3 shear_force = Vec3::Zero();  // tangential force on the lower-uid particle, world frame
  Vec3 normal = Vec3::Zero();       // contact normal of the last step (zero: none yet)
  PairState kernel;                 // kernel warm start
  std::uint32_t touching = 0;       // 1 if the pair was in contact at the last step
};

/// A sub-contact's key in the table: the features of A and B it comes from (a
/// contact::FeatureKey); its pair is the block it lies in.
struct SubFeature {
  std::uint64_t feature = 0;
  friend bool operator==(const SubFeature&, const SubFeature&) = default;
  friend auto operator<=>(const SubFeature&, const SubFeature&) = default;
};

/// A sub-contact's full key, for histories outside the table (in transit, in checkpoints): its
/// pair, then its features, so that a pair's sub-contacts sort together in a canonical order.
struct SubKey {
  PairKey pair;
  std::uint64_t feature = 0;
  friend bool operator==(const SubKey&, const SubKey&) = default;
  friend auto operator<=>(const SubKey&, const SubKey&) = default;
};

/// The most history values a joint law keeps per sub-contact (dynamics/joint_law.h).
inline constexpr std::size_t kMaxLawHistory = 2;

struct SubHistory {
  Vec3 shear_force = Vec3::Zero();  // on the lower-uid particle, world frame, tangent to `normal`
  Vec3 normal = Vec3::Zero();       // the sub-contact's normal at the last step
  // The joint law's history values (its kHistoryColumns, the rest 0); all 0 for material pairs
  // and coulomb joints.
  std::array<double, kMaxLawHistory> law{};
  bool hasLawState() const { return law[0] != 0.0 || law[1] != 0.0; }
};

/// A sub-contact's feature and history as its pair's contact law leaves them (the pair implied).
struct SubEntry {
  std::uint64_t feature = 0;
  SubHistory history;
};

void pack(SendBuffer& out, const PairKey& key, const PairHistory& h);
void unpack(RecvBuffer& in, PairKey& key, PairHistory& h);
void pack(SendBuffer& out, const SubKey& key, const SubHistory& h);
void unpack(RecvBuffer& in, SubKey& key, SubHistory& h);

/// Room for a pair's sub-contacts (ContactHistory::openSubs): the caller writes the features and
/// the histories of the first n slots in order.
struct SubSlots {
  std::span<SubFeature> keys;
  std::span<SubHistory> entries;
};

/// Histories in transit (received from other ranks, read from a checkpoint), in any order.
struct HistoryRecords {
  std::vector<PairKey> keys;
  std::vector<PairHistory> entries;
  std::vector<SubKey> sub_keys;
  std::vector<SubHistory> sub_entries;
  bool empty() const { return keys.empty() && sub_keys.empty(); }
};

class ContactHistory {
 public:
  std::size_t size() const { return pairs_; }
  bool empty() const { return pairs_ == 0; }
  std::span<const PairKey> keys() const { return {keys_.data(), pairs_}; }
  std::span<const PairHistory> entries() const { return {entries_.data(), pairs_}; }
  std::size_t subCount() const { return subs_; }
  std::span<const SubFeature> subFeatures() const { return {sub_keys_.data(), subs_}; }
  std::span<const SubHistory> subEntries() const { return {sub_entries_.data(), subs_}; }
  /// Index range [first, last) of the sub-contacts of the pair at `pair_index`.
  std::pair<std::size_t, std::size_t> subsOf(std::size_t pair_index) const {
    return {subBegin(pair_index), sub_end_[pair_index]};
  }
  void clear();

  /// Heap bytes (capacities, core/memory.h) of the pair table (keys, entries, block ends) and of
  /// the sub-contact table, their room included.
  std::uint64_t pairBytes() const;
  std::uint64_t subBytes() const;

  /// Entry for `key`, or null. O(log n).
  const PairHistory* find(const PairKey& key) const;

  /// Index range [first, last) of the sub-contacts of `key` in subFeatures(). O(log n).
  std::pair<std::size_t, std::size_t> subRange(const PairKey& key) const;

  /// A pair's entries: its own (null if none) and its sub-contacts (features and entries,
  /// parallel).
  struct Found {
    const PairHistory* pair = nullptr;
    std::span<const SubFeature> sub_keys;
    std::span<const SubHistory> subs;
  };

  /// Starts rebuilding the table in place: the table becomes empty for appends, while last
  /// step's entries stay readable through takeOld, for keys in increasing order.
  void beginRebuild();
  /// Last step's entries of `key` during a rebuild, for keys visited in increasing order; the old
  /// entries below `key` are dropped. The pair entry is valid until the next appendSorted, the
  /// sub-contacts until closeSubs or the next takeOld.
  Found takeOld(const PairKey& key);
  /// The same when the old entries of `key` are not read (a pair evaluated ahead of the step).
  void skipOld(const PairKey& key) {
    takeOld(key);
    read_floor_ = old_sub_;
  }
  /// Ends the rebuild: old entries not taken are dropped, and room far beyond the table's size
  /// (more than twice a quarter's growth) is given back.
  void endRebuild();

  /// Appends an entry whose key is larger than every key so far (building in sorted order).
  /// Returns it, to be updated in place until the next append (the contact phase appends last
  /// step's entry and lets the kernel and the law write into it, instead of copying a working
  /// history in and out).
  PairHistory& appendSorted(const PairKey& key, const PairHistory& h);
  /// Appends the sub-contacts of pair `pair` (features strictly increasing, above those it has);
  /// `pair` must be the pair appended last.
  void appendSubs(const PairKey& pair, std::span<const SubEntry> subs);
  /// Room for up to `count` sub-contacts of the pair appended last, to be written in place (no
  /// copy through a buffer of the caller's) and closed by closeSubs before anything else. While
  /// the old block of the pair taken last is still read, the slots are a buffer of the table's
  /// whenever the table's own would reach it, copied in by closeSubs.
  SubSlots openSubs(std::size_t count);
  /// Keeps the first `used` slots of openSubs, drops the rest; throws (dropping them all) unless
  /// the pair's features are strictly increasing.
  void closeSubs(std::size_t used);

  /// Adds entries in any order (e.g. received from other ranks, or a checkpoint read in chunks),
  /// in place: the records are sorted (pass them by std::move to spare a copy), and the table
  /// grows by the entries it lacks, merged from its end, without a second copy of the table. Keeps
  /// one copy of keys present twice, the table's over the records' and the first of equal records
  /// (copies of the same pair from two ranks are identical by construction). Throws, leaving the
  /// table as it was, if a sub-contact's pair has no entry in the table or the records.
  void merge(HistoryRecords records);
  /// The same for pairs without sub-contacts.
  void merge(std::span<const PairKey> keys, std::span<const PairHistory> entries);

  /// Builds the table from records that come in rounds (a restart's chunks), in O(n log n) for
  /// n records in all, where merging round by round walks the whole table each time
  /// (contact_history_assembly.cpp). beginAssembly empties the table; each appendRecords adds a
  /// round's records (any order) unsorted to the table's own arrays; endAssembly sorts them in
  /// place and sets the blocks. The table is then the one merging the rounds one by one gives:
  /// the first copy of a key kept (the table's over a round's, the first of equal records within
  /// a round). Between begin and end the table is not to be read (merge and beginRebuild refuse).
  void beginAssembly();
  /// Throws, leaving the table empty (nothing half-built), if a sub-contact's pair is neither in
  /// this round nor in an earlier one, as merge does.
  void appendRecords(HistoryRecords records);
  void endAssembly();
  bool assembling() const { return assembling_; }
  /// Adds this history's entries for the pair at `pair_index` (pair and sub-contacts) to
  /// `records`.
  void copyPair(std::size_t pair_index, HistoryRecords& records) const;

  /// Sequential lookup for a caller visiting keys in increasing order (outside a rebuild):
  /// advances an internal cursor over the pairs; a pair's sub-contacts are then its block of the
  /// second table.
  class Cursor {
   public:
    explicit Cursor(const ContactHistory& h) : h_(h) {}
    const PairHistory* seek(const PairKey& key) {
      while (pos_ < h_.pairs_ && h_.keys_[pos_] < key) ++pos_;
      return pos_ < h_.pairs_ && h_.keys_[pos_] == key ? &h_.entries_[pos_] : nullptr;
    }
    /// The entries of `key`, found by one step of the walk, for keys visited in increasing order.
    Found find(const PairKey& key) {
      const PairHistory* pair = seek(key);
      // Every sub-contact has its pair's entry (indexSubs), so a pair without one has none.
      if (pair == nullptr) return {};
      const std::size_t first = h_.subBegin(pos_), count = h_.sub_end_[pos_] - first;
      return {pair, {h_.sub_keys_.data() + first, count}, {h_.sub_entries_.data() + first, count}};
    }
    /// The sub-contacts of `key` (features and entries, parallel), for keys visited in
    /// increasing order.
    std::pair<std::span<const SubFeature>, std::span<const SubHistory>> subs(const PairKey& key) {
      const Found found = find(key);
      return {found.sub_keys, found.subs};
    }

   private:
    const ContactHistory& h_;
    std::size_t pos_ = 0;
  };

 private:
  /// Throws Error("ContactHistory::" + what); out of line, away from the step's inline calls.
  [[noreturn]] static void refuse(const char* what);
  /// Throws the error of a sub-contact history whose pair has none (an inconsistent checkpoint).
  [[noreturn]] static void refuseOrphan(const PairKey& pair);
  /// Room for one more pair in front of the unread old ones: moves these to the end of the
  /// room, or grows it by a quarter (core/memory.h growthFor) when that is not enough.
  void makePairRoom();
  /// The same for `count` more sub-contacts, in front of those still to be read.
  void makeSubRoom(std::size_t count);
  /// Nothing old to read: the unread ranges empty, at the end of the room.
  void dropOld();
  /// Whether the features of the last pair's block are strictly increasing up to `last`,
  /// checking from `first` on (and the one before it, if the pair has it).
  bool increasingFrom(std::size_t first, std::size_t last) const;
  /// First sub-contact of pair `k` (the end of the block of pair k - 1).
  std::size_t subBegin(std::size_t k) const { return k == 0 ? 0 : sub_end_[k - 1]; }
  /// merge's steps (contact_history_merge.cpp): the sorted records' pairs the table lacks
  /// merged in, sub_end_ holding each pair's sub-contact count afterwards; then the sub-contacts
  /// the table lacks merged into their pairs' blocks, sub_end_ holding block ends again.
  void mergePairs(const HistoryRecords& sorted, std::size_t added);
  void mergeSubs(const HistoryRecords& sorted, std::size_t added);
  /// The assembly's steps (contact_history_assembly.cpp): the index in keys_ of an earlier
  /// round's pair (sorting the pairs appended since the last sort first), or refuseOrphan; the
  /// pairs sorted in place with one copy of each key, the sub-contacts' pair indices following;
  /// the sub-contacts sorted by (pair, feature) in place with one copy of each, block ends set.
  std::uint32_t assembledPair(const PairKey& key);
  void sortAssembledPairs();
  void sortAssembledSubs();
  PairHistory& place(const PairKey& key, const PairHistory& h) {
    keys_[pairs_] = key;
    entries_[pairs_] = h;
    sub_end_[pairs_] = subs_;
    return entries_[pairs_++];
  }

  // The room: every slot constructed (the vectors' sizes), so that the step's appends neither
  // construct nor check per slot. The table is [0, pairs_) and [0, subs_).
  std::vector<PairKey> keys_;
  std::vector<PairHistory> entries_;
  // Per pair: one past its last sub-contact in sub_keys_. Four bytes: a rank's table indexes at
  // most kMaxSubs sub-contacts (300 GB of them).
  std::vector<std::uint32_t> sub_end_;
  static constexpr std::size_t kMaxSubs = 0xffffffffu;
  std::vector<SubFeature> sub_keys_;
  std::vector<SubHistory> sub_entries_;
  std::size_t pairs_ = 0, subs_ = 0;
  // Last step's entries not yet taken, while rebuilding: pairs [old_pair_, old_end_), their
  // sub-contacts [old_sub_, old_sub_end_). Sub-contacts from read_floor_ on may still be read
  // (the old block of the pair taken last, until closeSubs). Outside a rebuild the ranges are
  // empty, at the end of the room.
  std::size_t old_pair_ = 0, old_end_ = 0, old_sub_ = 0, old_sub_end_ = 0, read_floor_ = 0;
  std::size_t open_ = 0;       // slots handed out by openSubs, not yet closed
  bool open_scratch_ = false;  // ... in the scratch buffers below
  bool rebuilding_ = false;
  // While assembling: per sub-contact, the index of its pair in keys_; the pairs [0,
  // sorted_pairs_) are sorted, with one copy of each key.
  bool assembling_ = false;
  std::size_t sorted_pairs_ = 0;
  std::vector<std::uint32_t> sub_pair_;
  std::vector<SubFeature> scratch_keys_;
  std::vector<SubHistory> scratch_entries_;
};

// The calls made for every pair of every step, inline. appendSorted is forced inline: GCC keeps it
// a call from the contact phase otherwise, which costs the dense pack's hot loop a call per pair.

[[gnu::always_inline]] inline PairHistory& ContactHistory::appendSorted(const PairKey& key,
                                                                        const PairHistory& h) {
  if (pairs_ > 0 && !(keys_[pairs_ - 1] < key))
    refuse("appendSorted: keys must be strictly increasing");
  if (open_ > 0) refuse("appendSorted: sub-contact slots still open");
  if (pairs_ < old_pair_) return place(key, h);
  const PairHistory value = h;  // `h` may lie in the room that moves
  makePairRoom();
  return place(key, value);
}

inline ContactHistory::Found ContactHistory::takeOld(const PairKey& key) {
  while (old_pair_ < old_end_ && keys_[old_pair_] < key) old_sub_ = sub_end_[old_pair_++];
  read_floor_ = old_sub_;
  if (old_pair_ == old_end_ || keys_[old_pair_] != key) return {};
  // The pair's slot may be written from now on; its block is read until closeSubs.
  const std::size_t first = old_sub_, last = sub_end_[old_pair_];
  const PairHistory* pair = &entries_[old_pair_++];
  old_sub_ = last;
  return {
      pair, {sub_keys_.data() + first, last - first}, {sub_entries_.data() + first, last - first}};
}

inline SubSlots ContactHistory::openSubs(std::size_t count) {
  if (pairs_ == 0 || open_ > 0) refuse("openSubs: no pair appended, or slots still open");
  const std::size_t first = subs_;
  open_ = count;
  open_scratch_ = first + count > read_floor_;
  if (open_scratch_ && read_floor_ == old_sub_) {
    // No old block is being read: the unread ones may move now.
    makeSubRoom(count);
    open_scratch_ = false;
  }
  if (open_scratch_) {
    if (scratch_keys_.size() < count) {
      scratch_keys_.resize(count);
      scratch_entries_.resize(count);
    }
    return {{scratch_keys_.data(), count}, {scratch_entries_.data(), count}};
  }
  return {{sub_keys_.data() + first, count}, {sub_entries_.data() + first, count}};
}

inline bool ContactHistory::increasingFrom(std::size_t first, std::size_t last) const {
  // The whole block of the pair, with what an earlier openSubs of the same pair kept.
  const std::size_t block = subBegin(pairs_ - 1);
  for (std::size_t i = std::max(first, block + 1); i < last; ++i) {
    if (!(sub_keys_[i - 1].feature < sub_keys_[i].feature)) return false;
  }
  return true;
}

inline void ContactHistory::closeSubs(std::size_t used) {
  const std::size_t first = subs_, last = first + used;
  const bool scratch = open_scratch_;
  const bool fits = used <= open_;
  open_ = 0;
  open_scratch_ = false;
  read_floor_ = old_sub_;  // the old block of the pair has been read
  if (!fits) refuse("closeSubs: more than were opened");
  if (scratch) {
    if (last > read_floor_) makeSubRoom(used);
    std::copy_n(scratch_keys_.data(), used, sub_keys_.data() + first);
    std::copy_n(scratch_entries_.data(), used, sub_entries_.data() + first);
  }
  if (!increasingFrom(first, last)) refuse("closeSubs: features not increasing");
  subs_ = last;
  sub_end_[pairs_ - 1] = last;
}

}  // namespace polydem::particles

// Contact history: per-pair memory kept between steps, keyed by the ordered uid pair.
//
// It holds the tangential (shear) force, the previous contact normal (to rotate the shear force
// onto the new contact plane, Zhao eqs. 33-34) and the kernel's warm start (previous common plane
// or separating axis). With the sub-contact model (contact/face/face_contact.h) every sub-contact
// of a pair has a shear spring of its own, kept in a second table keyed by (pair, features). Both
// live outside the kernels so that they can migrate with particles and be written to checkpoints.
//
// Storage is two tables sorted by key; a pair's sub-contacts are contiguous in the second, and each
// pair keeps the end of its block there, so a pair's sub-contacts are found by its index, without
// a search. The narrow phase visits candidate pairs in the same key order, so looking up last
// step's entries is a merge walk (no hashing), and the new history comes out already sorted. A
// pair whose two particles are owned by different ranks is evaluated on both ranks from identical
// inputs, so both copies stay bit-for-bit equal.
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

/// A sub-contact's key: its pair, then the features of A and B it comes from (a
/// contact::FeatureKey), so that a pair's sub-contacts sort together in a canonical order.
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

/// Room for a pair's sub-contacts in the table (ContactHistory::openSubs): the pair's key is
/// filled in; the caller writes the features and the histories of the first n slots in order.
struct SubSlots {
  std::span<SubKey> keys;
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
  std::size_t size() const { return keys_.size(); }
  bool empty() const { return keys_.empty(); }
  std::span<const PairKey> keys() const { return keys_; }
  std::span<const PairHistory> entries() const { return entries_; }
  std::span<const SubKey> subKeys() const { return {sub_keys_.data(), subs_}; }
  std::span<const SubHistory> subEntries() const { return {sub_entries_.data(), subs_}; }
  void clear();

  /// Heap bytes (capacities, core/memory.h) of the pair table (keys, entries, block ends) and of
  /// the sub-contact table (its kept slots included).
  std::uint64_t pairBytes() const;
  std::uint64_t subBytes() const;

  /// Entry for `key`, or null. O(log n).
  const PairHistory* find(const PairKey& key) const;

  /// Index range [first, last) of the sub-contacts of `key` in subKeys(). O(log n).
  std::pair<std::size_t, std::size_t> subRange(const PairKey& key) const;

  /// Appends an entry whose key is larger than every key so far (building in sorted order).
  /// Returns it, to be updated in place until the next append (the contact phase appends last
  /// step's entry and lets the kernel and the law write into it, instead of copying a working
  /// history in and out).
  PairHistory& appendSorted(const PairKey& key, const PairHistory& h);
  /// Appends the sub-contacts of pair `pair` (features strictly increasing, above those it has);
  /// `pair` must be the pair appended last.
  void appendSubs(const PairKey& pair, std::span<const SubEntry> subs);
  /// Room for up to `count` sub-contacts of the pair appended last, to be written in place (no
  /// copy through a buffer of the caller's) and closed by closeSubs before anything else.
  SubSlots openSubs(std::size_t count);
  /// Keeps the first `used` slots of openSubs, drops the rest; throws (dropping them all) unless
  /// the pair's features are strictly increasing.
  void closeSubs(std::size_t used);

  /// Adds entries in any order (e.g. received from other ranks); sorts, and keeps one copy of
  /// keys present twice (copies of the same pair from two ranks are identical by construction).
  void merge(std::span<const PairKey> keys, std::span<const PairHistory> entries);
  /// The same for pairs and sub-contacts.
  void merge(const HistoryRecords& records);
  /// Adds this history's entries for `key` (pair and sub-contacts) to `records`.
  void copyPair(std::size_t pair_index, HistoryRecords& records) const;

  /// Sequential lookup for a caller visiting keys in increasing order: advances an internal cursor
  /// over the pairs; a pair's sub-contacts are then its block of the second table.
  class Cursor {
   public:
    explicit Cursor(const ContactHistory& h) : h_(h) {}
    const PairHistory* seek(const PairKey& key) {
      while (pos_ < h_.keys_.size() && h_.keys_[pos_] < key) ++pos_;
      return pos_ < h_.keys_.size() && h_.keys_[pos_] == key ? &h_.entries_[pos_] : nullptr;
    }
    /// A pair's entries: its own (null if none) and its sub-contacts (keys and entries, parallel).
    struct Found {
      const PairHistory* pair = nullptr;
      std::span<const SubKey> sub_keys;
      std::span<const SubHistory> subs;
    };
    /// The entries of `key`, found by one step of the walk (the contact phase needs both; asking
    /// seek and subs apart walked and compared twice), for keys visited in increasing order.
    Found find(const PairKey& key) {
      const PairHistory* pair = seek(key);
      // Every sub-contact has its pair's entry (indexSubs), so a pair without one has none.
      if (pair == nullptr) return {};
      const std::size_t first = h_.subBegin(pos_), count = h_.sub_end_[pos_] - first;
      return {pair, {h_.sub_keys_.data() + first, count}, {h_.sub_entries_.data() + first, count}};
    }
    /// The sub-contacts of `key` (keys and entries, parallel), for keys visited in increasing
    /// order.
    std::pair<std::span<const SubKey>, std::span<const SubHistory>> subs(const PairKey& key) {
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
  /// Room for at least `size` sub-contacts (slots constructed once, then kept), grown
  /// geometrically.
  void growSubs(std::size_t size);
  /// Room for one more pair, grown by a quarter (core/memory.h growthFor).
  void growPairs();
  /// Whether the features of the last pair's block are strictly increasing up to `last`,
  /// checking from `first` on (and the one before it, if the pair has it).
  bool increasingFrom(std::size_t first, std::size_t last) const;
  /// First sub-contact of pair `k` (the end of the block of pair k - 1).
  std::size_t subBegin(std::size_t k) const { return k == 0 ? 0 : sub_end_[k - 1]; }
  /// Recomputes sub_end_ from the two sorted tables; throws if a sub-contact has no pair entry.
  void indexSubs();

  std::vector<PairKey> keys_;
  std::vector<PairHistory> entries_;
  std::vector<std::size_t> sub_end_;  // per pair: one past its last sub-contact in sub_keys_
  // The sub-contacts are the first subs_ entries: slots past them are kept (constructed) from
  // earlier steps, so that openSubs in the step's loop neither constructs nor checks per slot.
  std::vector<SubKey> sub_keys_;
  std::vector<SubHistory> sub_entries_;
  std::size_t subs_ = 0;
  std::size_t open_ = 0;  // slots handed out by openSubs, not yet closed
};

// The calls made for every pair of every step, inline. appendSorted is forced inline: GCC keeps it
// a call from the contact phase otherwise, which costs the dense pack's hot loop a call per pair.

[[gnu::always_inline]] inline PairHistory& ContactHistory::appendSorted(const PairKey& key,
                                                                        const PairHistory& h) {
  if (!keys_.empty() && !(keys_.back() < key))
    refuse("appendSorted: keys must be strictly increasing");
  if (keys_.size() == keys_.capacity()) growPairs();
  keys_.push_back(key);
  entries_.push_back(h);
  sub_end_.push_back(subs_);
  return entries_.back();
}

inline SubSlots ContactHistory::openSubs(std::size_t count) {
  if (keys_.empty() || open_ > 0) refuse("openSubs: no pair appended, or slots still open");
  const std::size_t first = subs_;
  if (sub_keys_.size() < first + count) growSubs(first + count);
  const PairKey pair = keys_.back();
  for (std::size_t i = first; i < first + count; ++i) sub_keys_[i].pair = pair;
  open_ = count;
  return {{sub_keys_.data() + first, count}, {sub_entries_.data() + first, count}};
}

inline bool ContactHistory::increasingFrom(std::size_t first, std::size_t last) const {
  // The whole block of the pair, with what an earlier openSubs of the same pair kept.
  const std::size_t block = subBegin(keys_.size() - 1);
  for (std::size_t i = std::max(first, block + 1); i < last; ++i) {
    if (!(sub_keys_[i - 1].feature < sub_keys_[i].feature)) return false;
  }
  return true;
}

inline void ContactHistory::closeSubs(std::size_t used) {
  const std::size_t first = subs_, last = first + used;
  const bool valid = used <= open_ && increasingFrom(first, last);
  open_ = 0;
  if (!valid) refuse("closeSubs: more than were opened, or features not increasing");
  subs_ = last;
  sub_end_.back() = last;
}

}  // namespace polydem::particles

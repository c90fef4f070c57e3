// Contact history: per-pair memory kept between steps, keyed by the ordered uid pair.
//
// It holds the tangential (shear) force, the previous contact normal (to rotate the shear force
// onto the new contact plane, Zhao eqs. 33-34) and the kernel's warm start (previous common plane
// or separating axis). It lives outside the kernels so that it can migrate with particles and be
// written to checkpoints.
//
// Storage is a vector sorted by key. The narrow phase visits candidate pairs in the same key order,
// so looking up last step's entries is a merge walk (no hashing), and the new history comes out
// already sorted. A pair whose two particles are owned by different ranks is evaluated on both
// ranks from identical inputs, so both copies stay bit-for-bit equal.
#pragma once

#include <span>
#include <vector>

#include "contact/contact.h"
#include "core/byte_buffer.h"
#include "core/types.h"

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
  contact::PairState kernel;        // kernel warm start
  std::uint32_t touching = 0;       // 1 if the pair was in contact at the last step
};

void pack(SendBuffer& out, const PairKey& key, const PairHistory& h);
void unpack(RecvBuffer& in, PairKey& key, PairHistory& h);

class ContactHistory {
 public:
  std::size_t size() const { return keys_.size(); }
  bool empty() const { return keys_.empty(); }
  std::span<const PairKey> keys() const { return keys_; }
  std::span<const PairHistory> entries() const { return entries_; }
  void clear();

  /// Entry for `key`, or null. O(log n).
  const PairHistory* find(const PairKey& key) const;

  /// Appends an entry whose key is larger than every key so far (building in sorted order).
  void appendSorted(const PairKey& key, const PairHistory& h);

  /// Adds entries in any order (e.g. received from other ranks); sorts, and keeps one copy of
  /// keys present twice (copies of the same pair from two ranks are identical by construction).
  void merge(std::span<const PairKey> keys, std::span<const PairHistory> entries);

  /// Sequential lookup for a caller visiting keys in increasing order: advances an internal cursor.
  class Cursor {
   public:
    explicit Cursor(const ContactHistory& h) : h_(h) {}
    const PairHistory* seek(const PairKey& key);

   private:
    const ContactHistory& h_;
    std::size_t pos_ = 0;
  };

 private:
  std::vector<PairKey> keys_;
  std::vector<PairHistory> entries_;
};

}  // namespace polydem::particles

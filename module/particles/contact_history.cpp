#include "polydem/particles/contact_history.h"

#include <algorithm>

#include "polydem/core/error.h"
#include "polydem/core/memory.h"
#include "polydem/core/strings.h"

namespace polydem::particles {

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
  pairs_ = 0;
  subs_ = 0;
  open_ = 0;
  open_scratch_ = false;
  rebuilding_ = false;
  assembling_ = false;
  sorted_pairs_ = 0;
  std::vector<std::uint32_t>().swap(sub_pair_);
  dropOld();
}

void ContactHistory::refuseOrphan(const PairKey& pair) {
  throw Error(cat("ContactHistory: sub-contact history of pair (", pair.lo, ", ", pair.hi,
                  ") without the pair's own history (inconsistent data)"));
}

void ContactHistory::dropOld() {
  old_pair_ = old_end_ = keys_.size();
  old_sub_ = old_sub_end_ = read_floor_ = sub_keys_.size();
}

std::uint64_t ContactHistory::pairBytes() const {
  return capacityBytes(keys_) + capacityBytes(entries_) + capacityBytes(sub_end_);
}

std::uint64_t ContactHistory::subBytes() const {
  return capacityBytes(sub_keys_) + capacityBytes(sub_entries_) + capacityBytes(scratch_keys_) +
         capacityBytes(scratch_entries_) + capacityBytes(sub_pair_);
}

const PairHistory* ContactHistory::find(const PairKey& key) const {
  const auto end = keys_.begin() + static_cast<std::ptrdiff_t>(pairs_);
  const auto it = std::lower_bound(keys_.begin(), end, key);
  if (it == end || *it != key) return nullptr;
  return &entries_[static_cast<std::size_t>(it - keys_.begin())];
}

std::pair<std::size_t, std::size_t> ContactHistory::subRange(const PairKey& key) const {
  const auto end = keys_.begin() + static_cast<std::ptrdiff_t>(pairs_);
  const auto it = std::lower_bound(keys_.begin(), end, key);
  const auto k = static_cast<std::size_t>(it - keys_.begin());
  const std::size_t first = subBegin(k);
  return {first, it == end || *it != key ? first : sub_end_[k]};
}

void ContactHistory::beginRebuild() {
  if (rebuilding_ || open_ > 0 || assembling_) {
    refuse("beginRebuild: a rebuild, an assembly or slots still open");
  }
  // Last step's table stays where it is; the new one is written from the front, and the unread
  // old entries move to the end of the room only when the new ones reach them.
  old_pair_ = 0;
  old_end_ = pairs_;
  old_sub_ = 0;
  old_sub_end_ = subs_;
  read_floor_ = 0;
  pairs_ = 0;
  subs_ = 0;
  rebuilding_ = true;
}

namespace {

// Keeps [0, front) of `v`, moves [first, last) to the end of `room` slots (a new array when the
// room changes; move_backward within the array otherwise, the target at or after the source).
template <typename T>
void moveToEnd(std::vector<T>& v, std::size_t front, std::size_t first, std::size_t last,
               std::size_t room) {
  const auto at = [](auto& w, std::size_t i) { return w.begin() + static_cast<std::ptrdiff_t>(i); };
  if (room == v.size()) {
    std::move_backward(at(v, first), at(v, last), v.end());
    return;
  }
  std::vector<T> out(room);
  std::copy(v.begin(), at(v, front), out.begin());
  std::copy(at(v, first), at(v, last), at(out, room - (last - first)));
  v.swap(out);
}

// Room for `needed` slots: the current room, or a quarter more (at least `needed`).
std::size_t roomFor(std::size_t room, std::size_t needed) {
  return needed <= room ? room : std::max(needed, growthFor(room));
}

}  // namespace

void ContactHistory::makePairRoom() {
  const std::size_t unread = old_end_ - old_pair_;
  const std::size_t room = roomFor(keys_.size(), pairs_ + 1 + unread);
  moveToEnd(keys_, pairs_, old_pair_, old_end_, room);
  moveToEnd(entries_, pairs_, old_pair_, old_end_, room);
  moveToEnd(sub_end_, pairs_, old_pair_, old_end_, room);
  old_pair_ = room - unread;
  old_end_ = room;
}

void ContactHistory::makeSubRoom(std::size_t count) {
  // Nothing below read_floor_ is read any more: the unread sub-contacts are [read_floor_,
  // old_sub_end_), which old_sub_ and the block ends of the unread pairs point into.
  const std::size_t unread = old_sub_end_ - read_floor_;
  const std::size_t room = roomFor(sub_keys_.size(), subs_ + count + unread);
  if (room > kMaxSubs) refuse("makeSubRoom: more sub-contacts than 4-byte block ends can index");
  const std::size_t shift = room - unread - read_floor_;
  moveToEnd(sub_keys_, subs_, read_floor_, old_sub_end_, room);
  moveToEnd(sub_entries_, subs_, read_floor_, old_sub_end_, room);
  for (std::size_t k = old_pair_; k < old_end_; ++k) sub_end_[k] += shift;
  old_sub_ += shift;
  read_floor_ += shift;
  old_sub_end_ = room;
}

void ContactHistory::endRebuild() {
  if (!rebuilding_ || open_ > 0) refuse("endRebuild: no rebuild, or slots still open");
  rebuilding_ = false;
  // Room kept from a larger table is given back: the table keeps at most twice its growth.
  auto shrink = [](auto& v, std::size_t size) {
    if (v.size() > 2 * growthFor(size)) {
      v.resize(growthFor(size));
      v.shrink_to_fit();
    }
  };
  shrink(keys_, pairs_);
  shrink(entries_, pairs_);
  shrink(sub_end_, pairs_);
  shrink(sub_keys_, subs_);
  shrink(sub_entries_, subs_);
  dropOld();
}

void ContactHistory::appendSubs(const PairKey& pair, std::span<const SubEntry> subs) {
  if (subs.empty()) return;
  if (pairs_ == 0 || keys_[pairs_ - 1] != pair) {
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

void ContactHistory::copyPair(std::size_t pair_index, HistoryRecords& records) const {
  const PairKey& key = keys_[pair_index];
  records.keys.push_back(key);
  records.entries.push_back(entries_[pair_index]);
  const std::size_t first = subBegin(pair_index), last = sub_end_[pair_index];
  for (std::size_t s = first; s < last; ++s) {
    records.sub_keys.push_back({key, sub_keys_[s].feature});
    records.sub_entries.push_back(sub_entries_[s]);
  }
}

}  // namespace polydem::particles

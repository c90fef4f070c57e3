#include "polydem/sim/history_chunks.h"

#include <algorithm>
#include <cstdint>

namespace polydem::sim {

namespace {

// The most chunks of `records` any rank needs for `count` rows.
std::size_t chunksOnAnyRank(std::size_t count, std::size_t records, MPI_Comm comm) {
  std::uint64_t chunks = (count + records - 1) / records;
  MPI_Allreduce(MPI_IN_PLACE, &chunks, 1, MPI_UINT64_T, MPI_MAX, comm);
  return static_cast<std::size_t>(chunks);
}

// Rows [k x records, (k + 1) x records) of `from`, cut at its end.
template <typename T>
void take(std::vector<T>& to, const std::vector<T>& from, std::size_t k, std::size_t records) {
  const std::size_t first = std::min(from.size(), k * records);
  const std::size_t last = std::min(from.size(), first + records);
  to.assign(from.begin() + static_cast<std::ptrdiff_t>(first),
            from.begin() + static_cast<std::ptrdiff_t>(last));
}

}  // namespace

SavedHistoryChunks::SavedHistoryChunks(const CheckpointData& data, MPI_Comm comm,
                                       std::size_t records)
    : data_(data), records_(std::max<std::size_t>(records, 1)) {
  const HistoryView& view = data.history_view;
  pair_chunks_ =
      chunksOnAnyRank(view.table ? view.pairs.size() : data.pair_keys.size(), records_, comm);
  sub_chunks_ = chunksOnAnyRank(view.table ? 0 : data.sub_keys.size(), records_, comm);
}

bool SavedHistoryChunks::next(particles::HistoryRecords& chunk) {
  chunk = {};
  if (next_ >= pair_chunks_ + sub_chunks_) return false;
  const HistoryView& view = data_.history_view;
  if (view.table) {  // pairs with their sub-contacts, from the table
    const std::size_t first = std::min(view.pairs.size(), next_ * records_);
    const std::size_t last = std::min(view.pairs.size(), first + records_);
    for (std::size_t i = first; i < last; ++i) view.table->copyPair(view.pairs[i], chunk);
  } else if (next_ < pair_chunks_) {
    take(chunk.keys, data_.pair_keys, next_, records_);
    take(chunk.entries, data_.pair_histories, next_, records_);
  } else {
    take(chunk.sub_keys, data_.sub_keys, next_ - pair_chunks_, records_);
    take(chunk.sub_entries, data_.sub_histories, next_ - pair_chunks_, records_);
  }
  ++next_;
  return true;
}

}  // namespace polydem::sim

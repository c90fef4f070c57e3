// The checksum of a checkpoint dataset ("polydem-sum64", docs/checkpoint.md): a 64-bit hash of a
// dataset's elements in their global row-major order, built so that each rank can hash its own
// contiguous slice and the slices combine by plain addition. The checksum is therefore the same
// whatever the number of ranks that wrote or read the file, and whatever order they finish in.
//
// For element j (counted from 0 over the whole dataset) with bit pattern u_j (its little-endian
// bytes read as an unsigned integer of the element's size, zero-extended to 64 bits):
//
//   t_j      = mix64(u_j + (j + 1) * G)          (mod 2^64), G = 0x9e3779b97f4a7c15
//   checksum = mix64((sum over j of t_j) xor E)  (mod 2^64), E = number of elements
//
// mix64 is the SplitMix64 finaliser (BitHasher::mix in core/state_hash.h). mix64 is a bijection,
// so changing any single element always changes the checksum; any other corruption goes unnoticed
// with probability about 2^-64. It guards against damaged files, not against deliberate forgery.
// Strings are hashed byte by byte. python_coupling/scripts/checkpoint_summary.py recomputes it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

namespace polydem::hdf5 {

inline constexpr std::uint64_t kChecksumGamma = 0x9e3779b97f4a7c15ULL;

/// This slice's share of the sum over t_j: `count` elements of `element_size` bytes (1, 4 or 8)
/// at `data`, the first being element `first_index` of the dataset.
std::uint64_t checksumPartial(const void* data, std::size_t count, int element_size,
                              std::uint64_t first_index);

/// The checksum from the sum of all slices' partial sums (mod 2^64) and the element count.
std::uint64_t checksumFinish(std::uint64_t partial_sum, std::uint64_t element_count);

template <typename T>
std::uint64_t checksumPartial(std::span<const T> values, std::uint64_t first_index) {
  static_assert(sizeof(T) == 1 || sizeof(T) == 4 || sizeof(T) == 8);
  return checksumPartial(values.data(), values.size(), static_cast<int>(sizeof(T)), first_index);
}

/// Checksum of a whole byte string (e.g. the scene text: its "scene hash").
std::uint64_t checksumOfBytes(std::string_view bytes);

}  // namespace polydem::hdf5

// The dataset checksum: slices combine into the checksum of the whole whatever the split, and a
// change of any single element always changes it.
#include "polydem/hdf5/checksum.h"

#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "polydem/core/state_hash.h"

namespace polydem::checkpoint {
namespace {

/// The definition in docs/checkpoint.md, term by term.
template <typename U>
std::uint64_t reference(const std::vector<U>& values) {
  std::uint64_t sum = 0;
  for (std::size_t j = 0; j < values.size(); ++j) {
    sum += BitHasher::mix(static_cast<std::uint64_t>(values[j]) + (j + 1) * hdf5::kChecksumGamma);
  }
  return BitHasher::mix(sum ^ values.size());
}

template <typename U>
std::vector<U> sample(std::size_t n) {
  std::vector<U> v(n);
  std::uint64_t x = 12345;
  for (auto& e : v) {
    x = x * 6364136223846793005ULL + 1442695040888963407ULL;
    e = static_cast<U>(x >> 17);
  }
  return v;
}

template <typename U>
void checkSplits() {
  const auto v = sample<U>(1001);
  const std::uint64_t whole =
      hdf5::checksumFinish(hdf5::checksumPartial(std::span<const U>(v), 0), v.size());
  EXPECT_EQ(whole, reference(v));
  // Any split into contiguous slices, hashed in any order, gives the same checksum.
  for (std::size_t parts : {2u, 3u, 7u, 1001u}) {
    std::uint64_t sum = 0;
    for (std::size_t p = parts; p-- > 0;) {
      const std::size_t begin = v.size() * p / parts, end = v.size() * (p + 1) / parts;
      sum += hdf5::checksumPartial(std::span<const U>(v).subspan(begin, end - begin), begin);
    }
    EXPECT_EQ(hdf5::checksumFinish(sum, v.size()), whole) << parts << " slices";
  }
}

TEST(CheckpointChecksum, SlicesCombineIntoTheWhole) {
  checkSplits<std::uint8_t>();
  checkSplits<std::uint32_t>();
  checkSplits<std::uint64_t>();
}

TEST(CheckpointChecksum, AnySingleChangeIsDetected) {
  auto v = sample<std::uint64_t>(64);
  const std::uint64_t whole = reference(v);
  for (std::size_t j = 0; j < v.size(); ++j) {
    for (int bit : {0, 31, 63}) {
      auto w = v;
      w[j] ^= std::uint64_t{1} << bit;
      EXPECT_NE(hdf5::checksumFinish(hdf5::checksumPartial(std::span<const std::uint64_t>(w), 0),
                                     w.size()),
                whole);
    }
  }
  auto swapped = v;
  std::swap(swapped[3], swapped[40]);
  EXPECT_NE(reference(swapped), whole);
  // The element count is part of it: a trailing zero element is not invisible.
  auto longer = v;
  longer.push_back(0);
  EXPECT_NE(reference(longer), whole);
}

TEST(CheckpointChecksum, DoublesAreHashedByTheirBits) {
  const double values[2] = {0.0, -0.0};
  std::uint64_t bits[2];
  std::memcpy(bits, values, sizeof bits);
  EXPECT_NE(hdf5::checksumPartial(std::span<const double>(values, 1), 0),
            hdf5::checksumPartial(std::span<const double>(values + 1, 1), 0));
  EXPECT_EQ(hdf5::checksumPartial(std::span<const double>(values), 0),
            hdf5::checksumPartial(std::span<const std::uint64_t>(bits), 0));
  EXPECT_EQ(hdf5::checksumOfBytes("abc"),
            hdf5::checksumFinish(hdf5::checksumPartial(std::span<const char>("abc", 3), 0), 3));
}

}  // namespace
}  // namespace polydem::checkpoint

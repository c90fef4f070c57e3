#include "io/checkpoint_checksum.h"

#include <bit>
#include <cstring>

#include "core/error.h"
#include "core/state_hash.h"
#include "core/strings.h"

namespace polydem::io {

static_assert(std::endian::native == std::endian::little,
              "checkpoint checksums hash the little-endian bytes stored in the file");

namespace {

template <typename U>
std::uint64_t sumTerms(const void* data, std::size_t count, std::uint64_t first_index) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  // Four independent accumulators and keys let the multiplications of neighbouring elements
  // overlap; the sum is the same because addition mod 2^64 is associative.
  std::uint64_t s0 = 0, s1 = 0, s2 = 0, s3 = 0;
  std::uint64_t key = (first_index + 1) * kChecksumGamma;
  std::size_t i = 0;
  auto term = [&](std::size_t k, std::uint64_t key_k) {
    U u;
    std::memcpy(&u, bytes + k * sizeof(U), sizeof(U));
    return BitHasher::mix(static_cast<std::uint64_t>(u) + key_k);
  };
  for (; i + 4 <= count; i += 4) {
    s0 += term(i, key);
    s1 += term(i + 1, key + kChecksumGamma);
    s2 += term(i + 2, key + 2 * kChecksumGamma);
    s3 += term(i + 3, key + 3 * kChecksumGamma);
    key += 4 * kChecksumGamma;
  }
  for (; i < count; ++i, key += kChecksumGamma) s0 += term(i, key);
  return s0 + s1 + s2 + s3;
}

}  // namespace

std::uint64_t checksumPartial(const void* data, std::size_t count, int element_size,
                              std::uint64_t first_index) {
  switch (element_size) {
    case 1:
      return sumTerms<std::uint8_t>(data, count, first_index);
    case 4:
      return sumTerms<std::uint32_t>(data, count, first_index);
    case 8:
      return sumTerms<std::uint64_t>(data, count, first_index);
    default:
      throw Error(cat("checksumPartial: element size ", element_size, " is not 1, 4 or 8"));
  }
}

std::uint64_t checksumFinish(std::uint64_t partial_sum, std::uint64_t element_count) {
  return BitHasher::mix(partial_sum ^ element_count);
}

std::uint64_t checksumOfBytes(std::string_view bytes) {
  return checksumFinish(checksumPartial(bytes.data(), bytes.size(), 1, 0), bytes.size());
}

}  // namespace polydem::io

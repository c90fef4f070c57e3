#include "polydem/hdf5/checksum.h"

#include <bit>

#include "polydem/core/error.h"
#include "polydem/core/state_hash.h"
#include "polydem/core/strings.h"

namespace polydem::hdf5 {

static_assert(std::endian::native == std::endian::little,
              "checkpoint checksums hash the little-endian bytes stored in the file");

namespace {

// One loop per element size, written so that the compiler vectorises it. On x86-64 it is built
// twice, for the baseline and for AVX2 (4 elements per instruction, about 1.5-2x faster), and the
// loader picks the one the processor supports. Both compute the same integers, so the checksum
// does not depend on which one ran.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define POLYDEM_CHECKSUM_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define POLYDEM_CHECKSUM_CLONES
#endif

// The buffers hold doubles and signed integers; they are read as their bit patterns through
// types that may alias anything.
using U64 = std::uint64_t __attribute__((may_alias));
using U32 = std::uint32_t __attribute__((may_alias));

template <typename U>
std::uint64_t sumTerms(const U* values, std::size_t count, std::uint64_t first_index) {
  std::uint64_t sum = 0;
  for (std::size_t i = 0; i < count; ++i) {
    sum += BitHasher::mix(static_cast<std::uint64_t>(values[i]) +
                          (first_index + 1 + i) * kChecksumGamma);
  }
  return sum;
}

POLYDEM_CHECKSUM_CLONES std::uint64_t sum8(const U64* v, std::size_t n, std::uint64_t first) {
  return sumTerms(v, n, first);
}
POLYDEM_CHECKSUM_CLONES std::uint64_t sum4(const U32* v, std::size_t n, std::uint64_t first) {
  return sumTerms(v, n, first);
}
std::uint64_t sum1(const std::uint8_t* v, std::size_t n, std::uint64_t first) {
  return sumTerms(v, n, first);
}

}  // namespace

std::uint64_t checksumPartial(const void* data, std::size_t count, int element_size,
                              std::uint64_t first_index) {
  switch (element_size) {
    case 1:
      return sum1(static_cast<const std::uint8_t*>(data), count, first_index);
    case 4:
      return sum4(static_cast<const U32*>(data), count, first_index);
    case 8:
      return sum8(static_cast<const U64*>(data), count, first_index);
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

}  // namespace polydem::hdf5

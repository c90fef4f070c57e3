#include "polydem/domain/space_filling_curve.h"

#include <algorithm>
#include <utility>

#include "polydem/core/strings.h"
#include "polydem/domain/domain_error.h"

namespace polydem::domain {

namespace {

constexpr int kMaxBits = 21;  // 3 * 21 bits fit a 64-bit key

void checkBits(int bits) {
  if (bits < 1 || bits > kMaxBits) {
    throw DomainError(
        cat("space-filling curve: ", bits, " bits per axis, outside [1, ", kMaxBits, "]"));
  }
}

}  // namespace

std::uint64_t mortonKey(const Index3& c, int bits) {
  checkBits(bits);
  std::uint64_t key = 0;
  for (int j = bits - 1; j >= 0; --j) {
    for (int a = 2; a >= 0; --a) key = (key << 1) | ((static_cast<std::uint64_t>(c[a]) >> j) & 1);
  }
  return key;
}

std::uint64_t hilbertKey(const Index3& c, int bits) {
  checkBits(bits);
  std::uint32_t x[3] = {static_cast<std::uint32_t>(c[0]), static_cast<std::uint32_t>(c[1]),
                        static_cast<std::uint32_t>(c[2])};
  const std::uint32_t top = 1u << (bits - 1);
  // Skilling's inverse undo: walk the levels from the coarsest, reflecting or exchanging the
  // lower bits so that every sub-cube is visited in the orientation of the curve.
  for (std::uint32_t q = top; q > 1; q >>= 1) {
    const std::uint32_t p = q - 1;
    for (int i = 0; i < 3; ++i) {
      if (x[i] & q) {
        x[0] ^= p;
      } else {
        const std::uint32_t t = (x[0] ^ x[i]) & p;
        x[0] ^= t;
        x[i] ^= t;
      }
    }
  }
  // Gray encode across the axes.
  for (int i = 1; i < 3; ++i) x[i] ^= x[i - 1];
  std::uint32_t t = 0;
  for (std::uint32_t q = top; q > 1; q >>= 1) {
    if (x[2] & q) t ^= q - 1;
  }
  for (int i = 0; i < 3; ++i) x[i] ^= t;
  // The transposed index holds the key's bits spread over the axes, most significant first.
  std::uint64_t key = 0;
  for (int j = bits - 1; j >= 0; --j) {
    for (int i = 0; i < 3; ++i) key = (key << 1) | ((x[i] >> j) & 1u);
  }
  return key;
}

int curveBits(const BlockForest& forest) {
  const int n = std::max({forest.counts()[0], forest.counts()[1], forest.counts()[2]});
  int bits = 1;
  while ((1L << bits) < n) ++bits;
  return bits;
}

std::vector<int> sfcOrder(const BlockForest& forest, Curve curve) {
  const int bits = curveBits(forest);
  std::vector<std::pair<std::uint64_t, int>> keyed(forest.numBlocks());
  for (int b = 0; b < forest.numBlocks(); ++b) {
    const Index3 c = forest.blockCoords(b);
    keyed[b] = {curve == Curve::kHilbert ? hilbertKey(c, bits) : mortonKey(c, bits), b};
  }
  std::sort(keyed.begin(), keyed.end());  // keys are distinct
  std::vector<int> order(keyed.size());
  for (std::size_t i = 0; i < keyed.size(); ++i) order[i] = keyed[i].second;
  return order;
}

}  // namespace polydem::domain

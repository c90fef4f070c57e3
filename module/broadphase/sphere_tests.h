// The sphere tests of the grid searches (internal): one member (the probe) against two or four
// consecutive members of a grid's coordinate arrays at once, as a bit mask.
//
// Every width does the same IEEE operations in the same order as withinReach() ((dx^2 + dy^2) +
// dz^2 against ((r_a + r_b) + margin)^2, no FMA), lane by lane, so every width takes the same
// decisions bit for bit, and the searches write the same pairs in the same order whichever runs.
// Two lanes use SSE2, which every x86-64 CPU has (the build targets no more, by design: the same
// binary and the same bits on every machine). Four lanes use AVX2, compiled for the few functions
// that need it (a target attribute, not a build flag) and chosen at run time where the CPU has it.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define POLYDEM_BROADPHASE_AVX2 1
#else
#define POLYDEM_BROADPHASE_AVX2 0
#endif

#include "polydem/broadphase/cell_grid.h"
#include "polydem/broadphase/overlap.h"

namespace polydem::broadphase::detail {

/// Widths of the sphere tests.
enum class TestLanes { kTwo = 2, kFour = 4 };
/// The widest this CPU and this build run: kFour with AVX2, else kTwo.
TestLanes widestTestLanes();
/// The width the searches use: widestTestLanes() unless set.
TestLanes testLanes();
/// Sets the width for the whole process (tests cover the two-lane path on an AVX2 machine with
/// it). Throws polydem::Error for a width the CPU or the build lacks.
void setTestLanes(TestLanes lanes);

// A member of one grid held as the fixed side of a run of tests.
struct Probe {
  double x, y, z, r;
};

inline Probe probeOf(const Coords& c, std::int32_t k) {
  return {c.x[k], c.y[k], c.z[k], c.r[k]};
}

inline bool near(const Probe& a, const Coords& b, std::int32_t k, double margin) {
  return withinReach(a.x, a.y, a.z, a.r, b.x[k], b.y[k], b.z[k], b.r[k], margin);
}

/// The centres and largest radius of a run of queries (the cross-level search).
struct QueryBox {
  double lo[3], hi[3];
  double r_max;
};

/// Whether member k of `t` can be within reach of any sphere of radius <= box.r_max centred in
/// the box. Never false when withinReach() would be true for such a sphere: each term below is,
/// in floating point, at most the corresponding term of withinReach(). The vector versions do
/// the same operations (maxpd for std::max: the same values for finite inputs).
inline bool nearBox(const Coords& t, std::int32_t k, const QueryBox& box, double margin) {
  // Distance to the box along each axis (0 inside).
  const double dx = std::max(std::max(box.lo[0] - t.x[k], t.x[k] - box.hi[0]), 0.0);
  const double dy = std::max(std::max(box.lo[1] - t.y[k], t.y[k] - box.hi[1]), 0.0);
  const double dz = std::max(std::max(box.lo[2] - t.z[k], t.z[k] - box.hi[2]), 0.0);
  const double reach = box.r_max + t.r[k] + margin;
  return dx * dx + dy * dy + dz * dz <= reach * reach;
}

/// near() for members k and k + 1 of `b`: bit l for member k + l.
struct TwoLanes {
  static constexpr std::int32_t kLanes = 2;
  static std::uint32_t near(const Probe& a, const Coords& b, std::int32_t k, double margin) {
#if defined(__SSE2__)
    const __m128d dx = _mm_sub_pd(_mm_set1_pd(a.x), _mm_loadu_pd(b.x + k));
    const __m128d dy = _mm_sub_pd(_mm_set1_pd(a.y), _mm_loadu_pd(b.y + k));
    const __m128d dz = _mm_sub_pd(_mm_set1_pd(a.z), _mm_loadu_pd(b.z + k));
    return within(
        dx, dy, dz,
        _mm_add_pd(_mm_add_pd(_mm_set1_pd(a.r), _mm_loadu_pd(b.r + k)), _mm_set1_pd(margin)));
#else
    return static_cast<std::uint32_t>(detail::near(a, b, k, margin)) |
           static_cast<std::uint32_t>(detail::near(a, b, k + 1, margin)) << 1;
#endif
  }

  /// nearBox() for members k and k + 1 of `t`: bit l for member k + l.
  static std::uint32_t nearBox(const Coords& t, std::int32_t k, const QueryBox& box,
                               double margin) {
#if defined(__SSE2__)
    const __m128d zero = _mm_setzero_pd();
    auto axis = [&](const double* c, double lo, double hi) {
      const __m128d v = _mm_loadu_pd(c + k);
      return _mm_max_pd(_mm_max_pd(_mm_sub_pd(_mm_set1_pd(lo), v), _mm_sub_pd(v, _mm_set1_pd(hi))),
                        zero);
    };
    const __m128d dx = axis(t.x, box.lo[0], box.hi[0]);
    const __m128d dy = axis(t.y, box.lo[1], box.hi[1]);
    const __m128d dz = axis(t.z, box.lo[2], box.hi[2]);
    return within(
        dx, dy, dz,
        _mm_add_pd(_mm_add_pd(_mm_set1_pd(box.r_max), _mm_loadu_pd(t.r + k)), _mm_set1_pd(margin)));
#else
    return static_cast<std::uint32_t>(detail::nearBox(t, k, box, margin)) |
           static_cast<std::uint32_t>(detail::nearBox(t, k + 1, box, margin)) << 1;
#endif
  }

#if defined(__SSE2__)
 private:
  // Bit l set where dx^2 + dy^2 + dz^2 <= reach^2 in lane l, summed as withinReach() sums.
  static std::uint32_t within(__m128d dx, __m128d dy, __m128d dz, __m128d reach) {
    const __m128d d2 =
        _mm_add_pd(_mm_add_pd(_mm_mul_pd(dx, dx), _mm_mul_pd(dy, dy)), _mm_mul_pd(dz, dz));
    return static_cast<std::uint32_t>(_mm_movemask_pd(_mm_cmple_pd(d2, _mm_mul_pd(reach, reach))));
  }
#endif
};

#if POLYDEM_BROADPHASE_AVX2
// For each mask of four hits, the 32-bit words of the pairs hit, in lane order, then padding: the
// permutation FourLanes::writeHits() packs them with.
constexpr std::array<std::array<std::int32_t, 8>, 16> compressTable() {
  std::array<std::array<std::int32_t, 8>, 16> table{};
  for (std::uint32_t mask = 0; mask < 16; ++mask) {
    std::size_t next = 0;
    for (std::int32_t lane = 0; lane < 4; ++lane) {
      if ((mask >> lane) & 1u) {
        table[mask][next++] = 2 * lane;
        table[mask][next++] = 2 * lane + 1;
      }
    }
  }
  return table;
}
alignas(32) inline constexpr std::array<std::array<std::int32_t, 8>, 16> kCompress =
    compressTable();

/// near() for members k .. k + 3 of `b`: bit l for member k + l. Only callable where the CPU has
/// AVX2 (testLanes() == kFour), from functions compiled for it.
struct FourLanes {
  static constexpr std::int32_t kLanes = 4;
  [[gnu::target("avx2")]] static std::uint32_t near(const Probe& a, const Coords& b, std::int32_t k,
                                                    double margin) {
    const __m256d dx = _mm256_sub_pd(_mm256_set1_pd(a.x), _mm256_loadu_pd(b.x + k));
    const __m256d dy = _mm256_sub_pd(_mm256_set1_pd(a.y), _mm256_loadu_pd(b.y + k));
    const __m256d dz = _mm256_sub_pd(_mm256_set1_pd(a.z), _mm256_loadu_pd(b.z + k));
    return within(dx, dy, dz,
                  _mm256_add_pd(_mm256_add_pd(_mm256_set1_pd(a.r), _mm256_loadu_pd(b.r + k)),
                                _mm256_set1_pd(margin)));
  }

  /// nearBox() for members k .. k + 3 of `t`: bit l for member k + l.
  [[gnu::target("avx2")]] static std::uint32_t nearBox(const Coords& t, std::int32_t k,
                                                       const QueryBox& box, double margin) {
    const __m256d dx = gap(t.x + k, box.lo[0], box.hi[0]);
    const __m256d dy = gap(t.y + k, box.lo[1], box.hi[1]);
    const __m256d dz = gap(t.z + k, box.lo[2], box.hi[2]);
    return within(dx, dy, dz,
                  _mm256_add_pd(_mm256_add_pd(_mm256_set1_pd(box.r_max), _mm256_loadu_pd(t.r + k)),
                                _mm256_set1_pd(margin)));
  }

  /// Writes the pairs (a_pos, k + l) of the lanes l set in `hits` (4 bits), in lane order, at
  /// `w` and returns the end of them: the four pairs are built in one register, the hits moved
  /// to its front by a permutation chosen by the mask, and all 32 bytes stored (room for four
  /// pairs is needed). Instead of a store and an add per lane.
  [[gnu::target("avx2")]] static CandidatePair* writeHits(CandidatePair* w, std::int32_t a_pos,
                                                          std::int32_t k, std::uint32_t hits) {
    static_assert(sizeof(CandidatePair) == 8 && offsetof(CandidatePair, j) == 4);
    const std::uint64_t first =
        static_cast<std::uint32_t>(a_pos) | std::uint64_t{static_cast<std::uint32_t>(k)} << 32;
    const __m256i pairs =  // (a_pos, k), (a_pos, k + 1), (a_pos, k + 2), (a_pos, k + 3)
        _mm256_add_epi32(_mm256_set1_epi64x(static_cast<long long>(first)),
                         _mm256_setr_epi32(0, 0, 0, 1, 0, 2, 0, 3));
    const __m256i order =
        _mm256_loadu_si256(reinterpret_cast<const __m256i*>(kCompress[hits].data()));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(w), _mm256_permutevar8x32_epi32(pairs, order));
    return w + ((0x4332322132212110ull >> (4 * hits)) & 0xF);  // + the number of bits set
  }

 private:
  // Bit l set where dx^2 + dy^2 + dz^2 <= reach^2 in lane l, summed as withinReach() sums.
  // _CMP_LE_OS is SSE2's cmplepd: false for NaN, as the scalar <=.
  [[gnu::target("avx2")]] static std::uint32_t within(__m256d dx, __m256d dy, __m256d dz,
                                                      __m256d reach) {
    const __m256d d2 = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)),
                                     _mm256_mul_pd(dz, dz));
    return static_cast<std::uint32_t>(
        _mm256_movemask_pd(_mm256_cmp_pd(d2, _mm256_mul_pd(reach, reach), _CMP_LE_OS)));
  }
  // Distance along one axis from four coordinates at c to [lo, hi] (0 inside).
  [[gnu::target("avx2")]] static __m256d gap(const double* c, double lo, double hi) {
    const __m256d v = _mm256_loadu_pd(c);
    return _mm256_max_pd(
        _mm256_max_pd(_mm256_sub_pd(_mm256_set1_pd(lo), v), _mm256_sub_pd(v, _mm256_set1_pd(hi))),
        _mm256_setzero_pd());
  }
};
#endif

}  // namespace polydem::broadphase::detail

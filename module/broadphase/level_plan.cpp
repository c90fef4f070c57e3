#include "polydem/broadphase/level_plan.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

namespace polydem::broadphase::detail {

namespace {

// Mantissa thresholds of 2^(1/4), 2^(2/4), 2^(3/4): the quarter-octave bin of a number in [1, 2).
constexpr double kTwo52 = 4503599627370496.0;
constexpr std::uint64_t kQuarter[3] = {
    static_cast<std::uint64_t>((1.1892071150027210667 - 1.0) * kTwo52),
    static_cast<std::uint64_t>((1.4142135623730950488 - 1.0) * kTwo52),
    static_cast<std::uint64_t>((1.6817928305074290861 - 1.0) * kTwo52)};
static_assert(kBinsPerOctave == 4, "radiusBin() splits an octave in four");

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

int radiusBin(double r, double max_radius) {
  const double ratio = max_radius / r;
  if (!(r > 0.0) || !(ratio < kInf)) return kBins - 1;
  if (!(ratio >= 1.0)) return 0;
  // log2 from the bits of the (normal, >= 1) double: exponent and the mantissa's quarter.
  const auto bits = std::bit_cast<std::uint64_t>(ratio);
  const int exponent = static_cast<int>((bits >> 52) & 0x7ff) - 1023;
  const std::uint64_t mantissa = bits & ((std::uint64_t{1} << 52) - 1);
  const int quarter =
      int(mantissa >= kQuarter[0]) + int(mantissa >= kQuarter[1]) + int(mantissa >= kQuarter[2]);
  return std::min(kBinsPerOctave * exponent + quarter, kBins - 1);
}

int LevelPlanner::plan(const SphereSet& spheres, double margin, const SceneBounds& bounds,
                       const BroadPhaseParams& params, std::vector<std::uint8_t>& level_of) {
  const std::size_t n = spheres.radii.size();
  level_of.resize(n);
  if (n == 0) return 0;
  if (!(bounds.max_radius > 0.0)) {
    std::fill(level_of.begin(), level_of.end(), std::uint8_t{0});
    return 1;
  }
  if (params.gamma > 0.0) return planZhao(spheres, params, bounds.max_radius, level_of);
  return planByCost(spheres, margin, bounds, params, level_of);
}

int LevelPlanner::planZhao(const SphereSet& spheres, const BroadPhaseParams& params,
                           double max_radius, std::vector<std::uint8_t>& level_of) {
  // Zhao section 4: group k (0-based) holds D/gamma^(k+1) < r <= D/gamma^k, i.e.
  // k = floor(log_gamma(D / r)); the last allowed group takes everything smaller.
  const int last = (params.levels > 0 ? std::min(params.levels, kMaxLevels) : kMaxLevels) - 1;
  const double inv_log_gamma = 1.0 / std::log(params.gamma);
  std::array<std::int64_t, kMaxLevels> count{};
  for (std::size_t i = 0; i < level_of.size(); ++i) {
    const double r = spheres.radii[i];
    int k = last;
    if (r > 0.0) {
      const double g = std::floor(std::log(max_radius / r) * inv_log_gamma);
      if (g < last) k = std::max(0, static_cast<int>(g));
    }
    level_of[i] = static_cast<std::uint8_t>(k);
    ++count[k];
  }
  // Drop empty groups: renumber the populated ones consecutively.
  std::array<std::uint8_t, kMaxLevels> renumber{};
  int levels = 0;
  for (int k = 0; k <= last; ++k) {
    renumber[k] = static_cast<std::uint8_t>(levels);
    if (count[k] > 0) ++levels;
  }
  for (auto& l : level_of) l = renumber[l];
  return levels;
}

double LevelPlanner::levelCost(double n, double d, double below_r, double below_n, double margin,
                               double volume, double cell_factor) const {
  if (n <= 0.0) return 0.0;
  if (n <= static_cast<double>(kDirectMax)) return kLevelCost + 0.5 * n * (n - 1.0) + below_n * n;
  const double edge = cell_factor * (2.0 * d + margin);
  const double per_cell = std::min(n, n * edge * edge * edge / volume);
  const double within = 13.5 * n * per_cell + kLookupCost * 5.0 * n / std::max(per_cell, 1.0);
  // A smaller particle's reach box has width 2 (r + d + margin): 1 + width / edge cells a side.
  const double side = 1.0 + 2.0 * (below_r + d + margin) / edge;
  const double across = side * side * side * (kLookupCost + per_cell);
  return kLevelCost + within + below_n * across;
}

int LevelPlanner::planByCost(const SphereSet& spheres, double margin, const SceneBounds& bounds,
                             const BroadPhaseParams& params, std::vector<std::uint8_t>& level_of) {
  const double max_radius = bounds.max_radius;
  count_.fill(0);
  max_r_.fill(0.0);
  static_assert(kBins <= 256, "bins are kept in level_of until the levels are known");
  for (std::size_t i = 0; i < level_of.size(); ++i) {
    const double r = spheres.radii[i];
    const int b = radiusBin(r, max_radius);
    level_of[i] = static_cast<std::uint8_t>(b);
    ++count_[b];
    max_r_[b] = std::max(max_r_[b], r);
  }
  // The populated bins, largest radii first; prefix counts over them.
  std::array<int, kBins> bins{};
  int nb = 0;
  for (int b = 0; b < kBins; ++b) {
    if (count_[b] > 0) bins[nb++] = b;
  }
  std::array<double, kBins + 1> prefix{};
  for (int u = 0; u < nb; ++u) prefix[u + 1] = prefix[u] + static_cast<double>(count_[bins[u]]);
  const double total = prefix[nb];

  // Volume the particles are spread over: the centres' box padded by a median sphere, or the
  // packed volume of the spheres if that is smaller (a far ghost must not make the pack look
  // empty, a huge boundary block must not make it look full).
  double median_r = max_r_[bins[nb - 1]];
  for (int u = nb - 1; u >= 0; --u) {
    if (total - prefix[u] >= 0.5 * total) {
      median_r = max_r_[bins[u]];
      break;
    }
  }
  double box = 1.0, packed = 0.0;
  for (int k = 0; k < 3; ++k) box *= bounds.hi[k] - bounds.lo[k] + 2.0 * median_r + margin;
  for (int u = 0; u < nb; ++u) {
    const double side = 2.0 * max_r_[bins[u]] + margin;
    packed += static_cast<double>(count_[bins[u]]) * side * side * side;
  }
  const double volume = std::max(std::min(box, packed), std::numeric_limits<double>::min());

  // best[j][e]: least cost of the first e populated bins in at most j levels; from[j][e]: where
  // the last of those levels starts.
  const int max_levels =
      std::min(nb, params.levels > 0 ? std::min(params.levels, kMaxLevels) : kMaxLevels);
  for (int e = 0; e <= nb; ++e) best_[0][e] = e == 0 ? 0.0 : kInf;
  for (int j = 1; j <= max_levels; ++j) {
    for (int e = 0; e <= nb; ++e) {
      best_[j][e] = best_[j - 1][e];
      from_[j][e] = -1;  // "no new level": same as with j - 1 levels
      const double below_r = e < nb ? max_r_[bins[e]] : 0.0;
      const double below_n = total - prefix[e];
      for (int s = e - 1; s >= 0; --s) {
        if (best_[j - 1][s] == kInf) continue;
        const double cost =
            best_[j - 1][s] + levelCost(prefix[e] - prefix[s], max_r_[bins[s]], below_r, below_n,
                                        margin, volume, params.cell_factor);
        if (cost < best_[j][e]) {
          best_[j][e] = cost;
          from_[j][e] = s;
        }
      }
    }
  }
  // Walk back: the bins of each level, numbered from the largest spheres.
  std::array<int, kMaxLevels + 1> starts{};
  int levels = 0;
  for (int j = max_levels, e = nb; e > 0;) {
    while (from_[j][e] < 0) --j;
    starts[levels++] = from_[j][e];
    e = from_[j][e];
    --j;
  }
  std::reverse(starts.begin(), starts.begin() + levels);
  for (int l = 0; l < levels; ++l) {
    const int end = l + 1 < levels ? starts[l + 1] : nb;
    for (int u = starts[l]; u < end; ++u) level_of_bin_[bins[u]] = static_cast<std::uint8_t>(l);
  }
  for (auto& l : level_of) l = level_of_bin_[l];
  return levels;
}

}  // namespace polydem::broadphase::detail

#include "cube_layer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "polydem/broadphase/cell_order.h"
#include "polydem/core/error.h"
#include "polydem/core/strings.h"

namespace polydem::bench {

namespace {

constexpr double kBigEdge = 1.0;    // Zhao table 7
constexpr double kSmallEdge = 0.1;  // Zhao table 7
constexpr int kLayerSlots = 2;      // the layer is two big slots high

// Generator arithmetic written out, so the scene is the same with every standard library.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed) {}
  double unit() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  std::uint64_t below(std::uint64_t n) { return engine_() % n; }
  template <typename T>
  void shuffle(std::vector<T>& v) {
    for (std::size_t i = v.size(); i > 1; --i) std::swap(v[i - 1], v[below(i)]);
  }

 private:
  std::mt19937_64 engine_;
};

double circumradius(double edge) {
  return 0.5 * std::sqrt(3.0) * edge;
}

// Slot s of a layer kLayerSlots high on a footprint nx wide: bottom layer first.
Vec3 slotOrigin(int s, int nx, int ny, double pitch) {
  return pitch * Vec3(s % nx, (s / nx) % ny, s / (nx * ny));
}

void footprint(int slots, int& nx, int& ny) {
  nx = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(slots) / kLayerSlots)));
  ny = (slots + kLayerSlots * nx - 1) / (kLayerSlots * nx);
}

// A cube of `edge` in a free box of side `room_side` at `origin`, jittered inside it.
Vec3 jittered(const Vec3& origin, double room_side, double edge, Rng& rng) {
  const double room = room_side - edge;
  return origin + Vec3::Constant(0.5 * edge) + room * Vec3(rng.unit(), rng.unit(), rng.unit());
}

void addCube(CubeLayer& layer, const Vec3& centre, double edge) {
  layer.centers.push_back(centre);
  layer.radii.push_back(circumradius(edge));
  (edge == kBigEdge ? layer.big : layer.small) += 1;
}

// Returns the footprint width (m) along x and y.
Vec3 pockets(const CubeLayerSpec& spec, int n_big, int n_small, CubeLayer& layer, Rng& rng) {
  const double pitch = kBigEdge + spec.gap;
  const int per_axis = static_cast<int>(std::floor(pitch / (kSmallEdge + spec.gap)));
  const int capacity = per_axis * per_axis * per_axis;
  const double sub = pitch / per_axis;
  const int n_pockets = (n_small + capacity - 1) / capacity;
  // kind[s]: -1 a big cube, else the number of small cubes in the pocket.
  std::vector<int> kind(n_big, -1);
  for (int p = 0; p < n_pockets; ++p) kind.push_back(std::min(capacity, n_small - p * capacity));
  rng.shuffle(kind);
  int nx, ny;
  footprint(static_cast<int>(kind.size()), nx, ny);
  for (std::size_t s = 0; s < kind.size(); ++s) {
    const Vec3 origin = slotOrigin(static_cast<int>(s), nx, ny, pitch);
    if (kind[s] < 0) {
      addCube(layer, jittered(origin, pitch, kBigEdge, rng), kBigEdge);
      continue;
    }
    for (int i = 0; i < kind[s]; ++i) {  // fill the pocket from the bottom up
      const Vec3 cell(i % per_axis, (i / per_axis) % per_axis, i / (per_axis * per_axis));
      addCube(layer, jittered(origin + sub * cell, sub, kSmallEdge, rng), kSmallEdge);
    }
  }
  return Vec3(nx * pitch, ny * pitch, 0.0);
}

Vec3 sprinkle(const CubeLayerSpec& spec, int n_big, int n_small, CubeLayer& layer, Rng& rng) {
  // A slot is 11^3 small cells; the big cube takes the 10^3 corner, the 331 others form the gap.
  const double sub = kSmallEdge + spec.gap;
  const double pitch = 11.0 * sub;
  constexpr int kShell = 11 * 11 * 11 - 10 * 10 * 10;
  const int slots = std::max(n_big, (n_small + kShell - 1) / kShell);
  std::vector<std::uint8_t> has_big(slots, 0);
  std::fill(has_big.begin(), has_big.begin() + n_big, std::uint8_t{1});
  rng.shuffle(has_big);
  // The small cubes take n_small distinct gap cells chosen at random.
  std::vector<std::int32_t> gap_cells(static_cast<std::size_t>(slots) * kShell);
  for (std::size_t k = 0; k < gap_cells.size(); ++k) gap_cells[k] = static_cast<std::int32_t>(k);
  for (int k = 0; k < n_small; ++k) {
    std::swap(gap_cells[k], gap_cells[k + rng.below(gap_cells.size() - k)]);
  }
  std::sort(gap_cells.begin(), gap_cells.begin() + n_small);  // slot order in storage
  std::vector<std::array<int, 3>> shell;
  for (int z = 0; z < 11; ++z) {
    for (int y = 0; y < 11; ++y) {
      for (int x = 0; x < 11; ++x) {
        if (x == 10 || y == 10 || z == 10) shell.push_back({x, y, z});
      }
    }
  }
  int nx, ny;
  footprint(slots, nx, ny);
  int next_small = 0;
  for (int s = 0; s < slots; ++s) {
    const Vec3 origin = slotOrigin(s, nx, ny, pitch);
    if (has_big[s]) addCube(layer, jittered(origin, 10.0 * sub, kBigEdge, rng), kBigEdge);
    for (; next_small < n_small && gap_cells[next_small] / kShell == s; ++next_small) {
      const auto& c = shell[gap_cells[next_small] % kShell];
      addCube(layer, jittered(origin + sub * Vec3(c[0], c[1], c[2]), sub, kSmallEdge, rng),
              kSmallEdge);
    }
  }
  return Vec3(nx * pitch, ny * pitch, 0.0);
}

}  // namespace

CubeLayer makeCubeLayer(const CubeLayerSpec& spec) {
  if (spec.n < 1 || !(spec.big_fraction >= 0.0 && spec.big_fraction <= 1.0)) {
    throw Error(cat("cube layer: need n >= 1 and a big fraction in [0, 1], got n ", spec.n,
                    " and fraction ", spec.big_fraction));
  }
  const int n_big = static_cast<int>(std::lround(spec.big_fraction * spec.n));
  const int n_small = spec.n - n_big;
  CubeLayer layer;
  Rng rng(spec.seed);
  Vec3 size;
  if (spec.layout == "pockets") {
    size = pockets(spec, n_big, n_small, layer, rng);
  } else if (spec.layout == "sprinkle") {
    size = sprinkle(spec, n_big, n_small, layer, rng);
  } else {
    throw Error(cat("cube layer: unknown layout '", spec.layout, "'; known: pockets, sprinkle"));
  }
  // Dropped from `gap`: the lowest cubes float that far above the ground z = 0.
  for (Vec3& c : layer.centers) c.z() += spec.gap;
  if (spec.ground) {  // a slab 1 m thick under the whole footprint: one huge fixed body
    layer.centers.push_back(Vec3(0.5 * size.x(), 0.5 * size.y(), -0.5));
    layer.radii.push_back(0.5 * std::sqrt(size.x() * size.x() + size.y() * size.y() + 1.0));
  }
  const std::size_t n = layer.centers.size();
  layer.uids.resize(n);
  for (std::size_t i = 0; i < n; ++i) layer.uids[i] = i + 1;
  layer.active.assign(n, 1);
  if (spec.shuffle || spec.sort_cells) {
    std::vector<std::size_t> order(n);
    for (std::size_t i = 0; i < n; ++i) order[i] = i;
    if (spec.shuffle) {
      rng.shuffle(order);
    } else {
      // The order a simulation's periodic sort leaves (sim/step/sort.cpp): cells of the small
      // cubes' grid at zero margin.
      broadphase::CellOrder cells;
      const auto sorted = cells.order(layer.view(), n, 2.0 * circumradius(kSmallEdge));
      std::copy(sorted.begin(), sorted.end(), order.begin());
    }
    CubeLayer shuffled = layer;
    for (std::size_t i = 0; i < n; ++i) {
      shuffled.centers[i] = layer.centers[order[i]];
      shuffled.radii[i] = layer.radii[order[i]];
      shuffled.uids[i] = layer.uids[order[i]];
    }
    layer = std::move(shuffled);
  }
  return layer;
}

}  // namespace polydem::bench

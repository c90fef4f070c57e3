// The grids against the all-pairs reference and against pair counts known in closed form.
#include "polydem/broadphase/broad_phase.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "broadphase/scenes.h"
#include "polydem/broadphase/overlap.h"
#include "polydem/broadphase/sphere_tests.h"
#include "polydem/core/error.h"

namespace polydem::broadphase {
namespace {

using testing::latticeScene;
using testing::randomScene;
using testing::RandomSceneSpec;
using testing::Scene;

struct Method {
  std::string name;
  BroadPhaseParams params;
};

std::vector<Method> gridMethods() {
  return {{"multilevel", {}},
          {"multilevel", {.gamma = 2.0}},
          {"multilevel", {.gamma = 10.0, .levels = 2}},
          {"multilevel", {.levels = 1}},
          {"multilevel", {.cell_factor = 1.6}},
          {"nbs", {}},
          {"nbs", {.cell_factor = 2.3}}};
}

std::string describe(const Method& m) {
  return m.name + " (gamma " + std::to_string(m.params.gamma) + ", levels " +
         std::to_string(m.params.levels) + ", cell factor " + std::to_string(m.params.cell_factor) +
         ")";
}

// Checks the contract on one result and returns it sorted.
std::vector<CandidatePair> checkedSorted(const Scene& s, std::vector<CandidatePair> pairs,
                                         double margin) {
  for (const CandidatePair& p : pairs) {
    EXPECT_NE(p.i, p.j);
    EXPECT_LT(s.uids[p.i], s.uids[p.j]) << "pair not in uid order";
    EXPECT_TRUE(s.active[p.i] || s.active[p.j]) << "pair of two inactive particles";
    EXPECT_TRUE(spheresOverlap(s.centers[p.i], s.radii[p.i], s.centers[p.j], s.radii[p.j], margin));
  }
  std::sort(pairs.begin(), pairs.end(), [](const CandidatePair& a, const CandidatePair& b) {
    return a.i != b.i ? a.i < b.i : a.j < b.j;
  });
  EXPECT_TRUE(std::adjacent_find(pairs.begin(), pairs.end()) == pairs.end()) << "duplicate pair";
  return pairs;
}

// The pairs as the method returns them (its order).
std::vector<CandidatePair> runUnsorted(const std::string& name, const BroadPhaseParams& params,
                                       const Scene& s, double margin) {
  auto bp = makeBroadPhase(name, params);
  std::vector<CandidatePair> out = {{-1, -1}};  // must be cleared
  bp->findPairs(s.view(), margin, out);
  const auto stale = std::remove(out.begin(), out.end(), CandidatePair{-1, -1});
  EXPECT_TRUE(stale == out.end()) << name << " did not clear its output";
  out.erase(stale, out.end());
  return out;
}

std::vector<CandidatePair> run(const std::string& name, const BroadPhaseParams& params,
                               const Scene& s, double margin) {
  return checkedSorted(s, runUnsorted(name, params, s, margin), margin);
}

// The sphere-test widths this CPU runs: two lanes (SSE2) always, four with AVX2.
std::vector<detail::TestLanes> laneWidths() {
  std::vector<detail::TestLanes> widths = {detail::TestLanes::kTwo};
  if (detail::widestTestLanes() == detail::TestLanes::kFour) {
    widths.push_back(detail::TestLanes::kFour);
  }
  return widths;
}

// Runs the searches with `lanes`-wide sphere tests while it lives.
class LanesScope {
 public:
  explicit LanesScope(detail::TestLanes lanes) : saved_(detail::testLanes()) {
    detail::setTestLanes(lanes);
  }
  ~LanesScope() { detail::setTestLanes(saved_); }
  LanesScope(const LanesScope&) = delete;
  LanesScope& operator=(const LanesScope&) = delete;

 private:
  detail::TestLanes saved_;
};

// Every grid finds exactly the pairs of the reference, with every width of sphere test, and in
// the same order whatever the width; returns how many there are.
std::size_t expectSameAsReference(const Scene& s, double margin, const std::string& what) {
  const auto reference = run("all-pairs", {}, s, margin);
  for (const Method& m : gridMethods()) {
    std::vector<CandidatePair> two_lanes;
    for (const detail::TestLanes lanes : laneWidths()) {
      const LanesScope scope(lanes);
      const std::string where =
          what + ": " + describe(m) + ", " + std::to_string(static_cast<int>(lanes)) + " lanes";
      const auto pairs = runUnsorted(m.name, m.params, s, margin);
      EXPECT_EQ(checkedSorted(s, pairs, margin), reference) << where;
      if (lanes == detail::TestLanes::kTwo) {
        two_lanes = pairs;
      } else {
        EXPECT_EQ(pairs, two_lanes) << where << ": not in the order of two lanes";
      }
    }
  }
  return reference.size();
}

// Number of (lower index, higher index) pairs with at least one active member.
std::size_t activePairCount(const Scene& s, const std::vector<std::pair<int, int>>& pairs) {
  return std::count_if(pairs.begin(), pairs.end(),
                       [&](auto p) { return s.active[p.first] || s.active[p.second]; });
}

TEST(BroadPhase, RandomPolydisperseScenesMatchReference) {
  for (const double ratio : {1.0, 10.0, 100.0}) {
    for (const double fraction : {0.4, 0.02}) {
      RandomSceneSpec spec{.n = 600, .size_ratio = ratio, .solid_fraction = fraction};
      spec.seed = static_cast<std::uint64_t>(ratio * 10 + fraction * 100);
      const Scene s = randomScene(spec);
      for (const double margin : {0.0, 0.2}) {
        const std::size_t pairs = expectSameAsReference(
            s, margin,
            "ratio " + std::to_string(ratio) + ", fraction " + std::to_string(fraction) +
                ", margin " + std::to_string(margin));
        if (fraction > 0.1) {
          EXPECT_GT(pairs, 300u);
        }
      }
    }
  }
}

TEST(BroadPhase, InactiveGhostsNeverPairTogether) {
  const Scene s = randomScene(
      {.n = 800, .size_ratio = 10.0, .solid_fraction = 0.3, .inactive_fraction = 0.4, .seed = 5});
  expectSameAsReference(s, 0.1, "40% inactive");
  // All inactive: nothing at all.
  Scene ghosts = s;
  std::fill(ghosts.active.begin(), ghosts.active.end(), 0);
  for (const std::string name : {"multilevel", "nbs", "all-pairs"}) {
    EXPECT_TRUE(run(name, {}, ghosts, 0.1).empty()) << name;
  }
}

TEST(BroadPhase, HugeFixedBodyAmongSmallOnes) {
  for (const std::uint8_t huge_active : {0, 1}) {
    Scene s = randomScene({.n = 700, .size_ratio = 3.0, .solid_fraction = 0.3, .seed = 11});
    // A boundary block 1000 times larger, its surface through the middle of the pack.
    s.add(Vec3(4.0, 4.0, -1000.0 + 3.0), 1000.0, huge_active);
    s.add(Vec3(-3000.0, 0.0, 0.0), 900.0, 1);  // a second, far one touching nothing
    s.finish(3);
    expectSameAsReference(s, 0.05, "huge fixed body");
  }
}

TEST(BroadPhase, HugeAndTinyCoordinates) {
  for (const double scale : {1e-3, 1.0, 1e3}) {
    for (const double offset : {0.0, 1e6, -1e6}) {
      const Scene s = randomScene({.n = 400,
                                   .size_ratio = 10.0,
                                   .solid_fraction = 0.3,
                                   .inactive_fraction = 0.2,
                                   .scale = scale,
                                   .offset = Vec3(offset, -offset, offset),
                                   .seed = 17});
      expectSameAsReference(s, 0.1 * scale,
                            "scale " + std::to_string(scale) + " offset " + std::to_string(offset));
    }
  }
  // Millimetre grains at 1e6 m next to one far particle: a huge, nearly empty extent.
  Scene s =
      randomScene({.n = 300, .solid_fraction = 0.3, .scale = 1e-3, .offset = Vec3(1e6, 0, 0)});
  s.add(Vec3(-1e6, 5e5, 0.0), 1e-3);
  s.finish(4);
  expectSameAsReference(s, 0.0, "sparse extent");
}

// Lattice spacing 1, radius 1/2: face neighbours touch exactly (distance 1 = 1/2 + 1/2). With
// margin 1/2 the reach is 3/2: edge diagonals (sqrt 2) join, body diagonals (sqrt 3) do not.
// Power-of-two scales and offsets keep every coordinate exact, so the counts are exact.
TEST(BroadPhase, ExactlyTouchingLatticeCounts) {
  const int n = 7;
  const std::size_t faces = 3 * n * n * (n - 1);
  const std::size_t edges = 6 * n * (n - 1) * (n - 1);
  for (const double scale : {std::ldexp(1.0, -10), 1.0, std::ldexp(1.0, 10)}) {
    for (const double offset : {0.0, std::ldexp(1.0, 20), -std::ldexp(1.0, 20)}) {
      const Scene s = latticeScene(n, scale, 0.5 * scale, Vec3::Constant(offset));
      for (const std::string name : {"multilevel", "nbs", "all-pairs"}) {
        EXPECT_EQ(run(name, {}, s, 0.0).size(), faces) << name << " scale " << scale;
        EXPECT_EQ(run(name, {}, s, 0.5 * scale).size(), faces + edges) << name;
      }
    }
  }
  // Decimal scales are not exact: the grids must still agree with the reference bit for bit.
  for (const double scale : {1e-3, 0.1, 1e3}) {
    const Scene s = latticeScene(n, scale, 0.5 * scale, Vec3::Constant(1e6));
    expectSameAsReference(s, 0.0, "decimal lattice " + std::to_string(scale));
    expectSameAsReference(s, 0.5 * scale, "decimal lattice with margin");
  }
}

// Pairs at exactly the reach, a few ulps around multiples of the reach from the lowest centre:
// there the rounding of (x - x0) / edge can put the two members two cells apart unless the grid
// allows for it (an edge of exactly the reach misses about one such pair in a hundred here).
TEST(BroadPhase, TouchingPairsAtCellBorders) {
  for (const double lowest : {-2.3, 0.1, 3.7}) {
    const double r = 0.05, reach = 2.0 * r;
    Scene s;
    s.add(Vec3(lowest, 0.0, 0.0), r);  // the lowest centre: the cells start here
    int row = 1;
    for (int m = 2; m <= 400; ++m) {
      for (int ulps = -3; ulps <= 3; ++ulps) {
        double a = lowest + m * reach;
        for (int k = 0; k < std::abs(ulps); ++k) a = std::nextafter(a, ulps * 1e300);
        for (const double b : {a + reach, a - reach}) {
          const double y = 3.0 * reach * row++;
          s.add(Vec3(a, y, 0.0), r);
          s.add(Vec3(b, y, 0.0), r);
        }
      }
    }
    s.finish(12);
    const std::size_t pairs =
        expectSameAsReference(s, 0.0, "touching at cell borders from " + std::to_string(lowest));
    EXPECT_GT(pairs, 1000u);  // about a third of the rows round to within reach
  }
}

TEST(BroadPhase, TwoSizeLatticeTouchingAcrossLevels) {
  // Big spheres (radius 1/2) on a 5^3 lattice of spacing 1, and on each big sphere of the top
  // layer a small one (radius 1/32) touching it from above: distance 1/2 + 1/32 exactly.
  Scene s = latticeScene(5, 1.0, 0.5, Vec3::Zero());
  const std::size_t big = s.centers.size();
  for (std::size_t i = 0; i < big; ++i) {
    if (s.centers[i].z() == 4.0) s.add(s.centers[i] + Vec3(0, 0, 0.5 + 1.0 / 32), 1.0 / 32);
  }
  s.finish(8);
  const std::size_t faces = 3 * 25 * 4;
  for (const std::string name : {"multilevel", "nbs", "all-pairs"}) {
    EXPECT_EQ(run(name, {}, s, 0.0).size(), faces + 25) << name;
  }
  expectSameAsReference(s, 0.0, "two-size lattice");
}

TEST(BroadPhase, PocketsOfSmallAmongBigMatchReference) {
  // Zhao's P-BROADPHASE shape: big spheres on a jittered lattice, some slots filled instead with
  // a pocket of small ones 10x smaller, packed. The small level's cells are then a tenth of the
  // big level's, so the cross-level search takes runs of several small cells per box test (odd
  // and even run lengths, runs cut by rows and by the span); some of both sizes are ghosts.
  Scene s;
  int pockets = 0;
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> jitter(-0.01, 0.01);
  std::uniform_int_distribution<int> ghost(0, 4);
  for (int z = 0; z < 2; ++z) {
    for (int y = 0; y < 4; ++y) {
      for (int x = 0; x < 4; ++x) {
        const Vec3 slot(x, y, z);
        if ((x + 2 * y + 3 * z) % 3 != 0) {
          s.add(slot + Vec3(jitter(rng), jitter(rng), jitter(rng)), 0.55, ghost(rng) != 0);
          continue;
        }
        ++pockets;
        for (int k = 0; k < 9 * 9 * 9; ++k) {
          const Vec3 cell(k % 9, (k / 9) % 9, k / 81);
          const Vec3 c = slot + 0.1 * (cell - Vec3::Constant(4.0));
          s.add(c + Vec3(jitter(rng), jitter(rng), jitter(rng)), 0.06, ghost(rng) != 0);
        }
      }
    }
  }
  s.finish(22);
  for (const double margin : {0.0, 0.01}) {
    expectSameAsReference(s, margin, "pockets");
    // Face neighbours in a pocket are at most 0.1 + 2 * 0.01 apart, within 2 * 0.06: all pair
    // (unless both are ghosts); a pocket's outer small spheres reach the big ones next to it.
    const auto pairs = run("multilevel", {}, s, margin);
    const auto across = std::count_if(pairs.begin(), pairs.end(), [&](const CandidatePair& p) {
      return s.radii[p.i] != s.radii[p.j];
    });
    EXPECT_GT(pairs.size(), static_cast<std::size_t>(pockets * 3 * 9 * 9 * 8) * 9 / 10);
    EXPECT_GT(across, 100);
  }
}

TEST(BroadPhase, CoincidentCentresAndPointParticles) {
  // Groups of 1..6 particles sharing one centre, radius 0, margin 0: exactly the groups pair.
  Scene s;
  std::size_t expected = 0;
  for (int g = 1; g <= 6; ++g) {
    for (int k = 0; k < g; ++k) s.add(Vec3(g, 0.5 * g, 0.0), 0.0);
    expected += g * (g - 1) / 2;
  }
  s.finish(2);
  for (const std::string name : {"multilevel", "nbs", "all-pairs"}) {
    EXPECT_EQ(run(name, {}, s, 0.0).size(), expected) << name;
  }
  // All particles at one point: every pair, whatever the radii.
  Scene one;
  for (int k = 0; k < 50; ++k) one.add(Vec3(1e6, 1e6, 1e6), 0.01 * (k % 7));
  one.finish(6);
  for (const std::string name : {"multilevel", "nbs", "all-pairs"}) {
    EXPECT_EQ(run(name, {}, one, 0.0).size(), 50u * 49u / 2u) << name;
  }
}

TEST(BroadPhase, AllParticlesInOneCell) {
  Scene s = randomScene({.n = 300, .size_ratio = 1.0, .solid_fraction = 0.3, .scale = 0.001});
  std::vector<std::pair<int, int>> all;
  for (std::size_t i = 0; i < s.centers.size(); ++i) {
    s.radii[i] = 1.0 + 0.5 * (i % 3);  // far larger than the spread of the centres
    s.active[i] = i % 4 != 0;
    for (std::size_t j = i + 1; j < s.centers.size(); ++j) all.emplace_back(int(i), int(j));
  }
  for (const std::string name : {"multilevel", "nbs", "all-pairs"}) {
    EXPECT_EQ(run(name, {}, s, 0.0).size(), activePairCount(s, all)) << name;
  }
}

TEST(BroadPhase, EmptyAndSingleParticle) {
  Scene s;
  for (const std::string name : {"multilevel", "nbs", "all-pairs"}) {
    EXPECT_TRUE(run(name, {}, s, 0.0).empty()) << name;
  }
  s.add(Vec3(1, 2, 3), 0.5);
  s.finish(1);
  for (const std::string name : {"multilevel", "nbs", "all-pairs"}) {
    EXPECT_TRUE(run(name, {}, s, 1.0).empty()) << name;
  }
}

TEST(BroadPhase, RepeatedCallsGiveTheSameOutput) {
  const Scene s = randomScene({.n = 2000, .size_ratio = 30.0, .solid_fraction = 0.3, .seed = 9});
  for (const std::string name : {"multilevel", "nbs"}) {
    auto bp = makeBroadPhase(name);
    std::vector<CandidatePair> first, second;
    bp->findPairs(s.view(), 0.05, first);
    bp->findPairs(s.view(), 0.05, second);
    EXPECT_EQ(first, second) << name;  // same order too: the search is deterministic
    // A different scene in between and back: still the same.
    const Scene other = randomScene({.n = 100, .size_ratio = 2.0, .seed = 10});
    bp->findPairs(other.view(), 0.0, second);
    bp->findPairs(s.view(), 0.05, second);
    EXPECT_EQ(first, second) << name;
  }
}

TEST(BroadPhase, SphereTestWidths) {
  EXPECT_EQ(detail::testLanes(), detail::widestTestLanes());  // the widest by default
  if (detail::widestTestLanes() == detail::TestLanes::kTwo) {
    EXPECT_THROW(detail::setTestLanes(detail::TestLanes::kFour), Error);
  }
  for (const detail::TestLanes lanes : laneWidths()) {
    const LanesScope scope(lanes);
    EXPECT_EQ(detail::testLanes(), lanes);
  }
  EXPECT_EQ(detail::testLanes(), detail::widestTestLanes());
}

TEST(BroadPhase, NamesAndErrors) {
  EXPECT_EQ(broadPhaseNames().front(), "multilevel");
  for (const std::string& name : broadPhaseNames()) EXPECT_EQ(makeBroadPhase(name)->name(), name);
  try {
    makeBroadPhase("octree");
    FAIL() << "unknown name accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("multilevel, nbs, all-pairs"), std::string::npos);
  }
  EXPECT_THROW(makeBroadPhase("multilevel", {.gamma = 1.0}), Error);
  EXPECT_THROW(makeBroadPhase("multilevel", {.gamma = -2.0}), Error);
  EXPECT_THROW(makeBroadPhase("multilevel", {.levels = -1}), Error);
  EXPECT_THROW(makeBroadPhase("multilevel", {.levels = 17}), Error);
  EXPECT_THROW(makeBroadPhase("nbs", {.cell_factor = 0.9}), Error);

  Scene s = randomScene({.n = 10});
  std::vector<CandidatePair> out;
  for (const std::string& name : broadPhaseNames()) {
    auto bp = makeBroadPhase(name);
    EXPECT_THROW(bp->findPairs(s.view(), -1.0, out), Error) << name;
    EXPECT_THROW(bp->findPairs(s.view(), std::nan(""), out), Error) << name;
    SphereSet short_radii = s.view();
    short_radii.radii = short_radii.radii.first(9);
    EXPECT_THROW(bp->findPairs(short_radii, 0.0, out), Error) << name;
    Scene bad = s;
    bad.radii[3] = -0.1;
    EXPECT_THROW(bp->findPairs(bad.view(), 0.0, out), Error) << name;
    bad = s;
    bad.centers[4].y() = std::nan("");
    try {
      bp->findPairs(bad.view(), 0.0, out);
      FAIL() << name << " accepted a NaN centre";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("uid " + std::to_string(bad.uids[4])), std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace polydem::broadphase

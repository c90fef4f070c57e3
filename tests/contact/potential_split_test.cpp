// The region split of the potential kernels: splitting each boundary piece by the nearest-face
// partition's neighbours (what distance-potential does) gives the same force and moment as
// cutting every region out by every candidate plane, from shallow to deep overlaps; and neither
// potential kernel allocates once its buffers have grown.
#include <gtest/gtest.h>

#include <random>

#include "common/allocation_counter.h"
#include "polydem/contact/potential/distance_potential.h"
#include "polydem/contact/potential/fdem.h"
#include "polydem/contact/potential/potential_overlap.h"
#include "polydem/geometry/shapes.h"
#include "potential_test_util.h"

namespace polydem::contact {
namespace {

using testing::place;
using testing::Placed;
using testing::RandomPair;
using testing::randomPair;

// One cell for the whole body, as the distance-potential kernel builds it, with or without the
// shape's nearest-face partition (with: its neighbours and located regions, so that a region is
// clipped only by the neighbours whose shared facet meets the piece's plane).
struct BodyCell {
  std::vector<potential::CellPlane> planes;
  std::vector<Vec3> corners;
  std::vector<int> loops;
  std::vector<potential::CellFace> faces;
  bool partition = true;
  const geometry::FaceRegions* regions = nullptr;
  double tolerance = 0.0;

  BodyCell(const Body& body, const Vec3& origin, bool with_partition) : partition(with_partition) {
    const double inv_r = 1.0 / body.shape->inradius();
    for (std::size_t f = 0; f < body.shape->faces().size(); ++f) {
      const auto& face = body.shape->faces()[f];
      const Vec3 n = body.rotation * face.normal;
      planes.push_back({n, face.offset + n.dot(body.position - origin), inv_r});
      faces.push_back({static_cast<int>(f), static_cast<int>(loops.size()), 0});
      loops.insert(loops.end(), face.vertices.begin(), face.vertices.end());
      faces.back().end = static_cast<int>(loops.size());
    }
    for (const Vec3& v : body.vertices) corners.push_back(v - origin);
    regions = &body.shape->faceRegions();
    tolerance = 1e-9 * body.shape->lengthScale();
  }
  potential::Cell cell() const {
    if (!partition) return {planes, corners, loops, faces, {}, {}, {}};
    return {planes,
            corners,
            loops,
            faces,
            regions->begin,
            regions->neighbours,
            {regions->corner_begin, regions->corners, regions->facets, regions->basis, tolerance}};
  }
};

potential::OverlapSums integrate(const Body& a, const Body& b, bool with_partition) {
  Vec3 lo, hi;
  EXPECT_TRUE(potential::commonBox(a.vertices, b.vertices, lo, hi));
  const Vec3 origin = 0.5 * (lo + hi);
  const BodyCell ca(a, origin, with_partition), cb(b, origin, with_partition);
  potential::OverlapIntegrator integrator;
  potential::OverlapSums sums;
  std::vector<Vec3> corners;
  integrator.add(ca.cell(), cb.cell(), lo - origin, hi - origin, sums, corners);
  return sums;
}

TEST(PotentialSplit, PartitionNeighboursGiveTheSameIntegralsAsEveryCandidate) {
  int pairs = 0;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    for (double depth : {1e-4, 0.05, 0.6}) {
      const RandomPair p = randomPair(seed, depth);
      const auto fast = integrate(p.a.body, p.b.body, true);
      const auto full = integrate(p.a.body, p.b.body, false);
      const double size = p.a.body.circumradius() + p.b.body.circumradius();
      const double scale = full.phi_integral;  // |force| <= this (m^2)
      ASSERT_GT(scale, 0.0) << seed << " " << depth;
      EXPECT_LT((fast.force - full.force).norm(), 1e-12 * scale) << seed << " " << depth;
      EXPECT_LT((fast.moment - full.moment).norm(), 1e-12 * scale * size) << seed << " " << depth;
      EXPECT_NEAR(fast.phi_integral, full.phi_integral, 1e-12 * scale) << seed << " " << depth;
      EXPECT_NEAR(fast.area, full.area, 1e-12 * full.area) << seed << " " << depth;
      ++pairs;
    }
  }
  EXPECT_EQ(pairs, 18);
}

// B's faces are clipped only by the planes of A whose faces may meet B (once A gave a piece):
// the boundary pieces must still cover exactly the overlap's surface, and separated pairs whose
// boxes overlap must give none.
TEST(PotentialSplit, BoundaryPiecesCoverTheOverlapsSurface) {
  int overlapping = 0, separated = 0;
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    for (double depth : {-0.05, 1e-4, 0.05, 0.6}) {
      const RandomPair p = randomPair(seed, depth);
      Vec3 lo, hi;
      if (!potential::commonBox(p.a.body.vertices, p.b.body.vertices, lo, hi)) continue;
      const auto sums = integrate(p.a.body, p.b.body, true);
      const auto v =
          testing::overlapPolyhedron(testing::worldShape(p.a.body), testing::worldShape(p.b.body));
      if (depth < 0.0) {
        EXPECT_FALSE(v.has_value()) << seed;
        EXPECT_EQ(sums.area, 0.0) << seed;
        ++separated;
        continue;
      }
      ASSERT_TRUE(v.has_value()) << seed << " " << depth;
      double area = 0.0;
      for (const auto& f : v->faces()) area += f.area;
      EXPECT_NEAR(sums.area, area, 1e-9 * area) << seed << " " << depth;
      ++overlapping;
    }
  }
  EXPECT_EQ(overlapping, 36);
  EXPECT_GT(separated, 0);
}

TEST(PotentialSplit, KernelsAllocateNothingOnceWarm) {
  // Random pairs from shallow to deep, and cubes face on face in random poses.
  std::vector<RandomPair> pairs;
  for (std::uint64_t seed = 40; seed < 43; ++seed) {
    for (double depth : {1e-3, 0.1, 0.5}) pairs.push_back(randomPair(seed, depth));
  }
  std::mt19937_64 rng(9);
  std::vector<std::pair<Placed, Placed>> cubes;
  for (int k = 0; k < 6; ++k) {
    const Mat3 rot = testing::randomRotation(rng);
    const Mat3 turn = testing::rotationAbout(Vec3::UnitZ(), 0.1 * k);
    cubes.emplace_back(
        place(geometry::shapes::cube(1.0), rot * Vec3(0.1, 0.05, 1.0 - 1e-4), rot * turn),
        place(geometry::shapes::cube(1.0), Vec3::Zero(), rot));
  }
  const DistancePotentialKernel distance_potential;
  const FdemKernel fdem;
  auto sweep = [&] {
    int touching = 0;
    for (const auto& p : pairs) {
      touching += distance_potential.collide(p.a.body, p.b.body, nullptr).touching;
      touching += fdem.collide(p.a.body, p.b.body, nullptr).touching;
    }
    for (const auto& [a, b] : cubes) {
      touching += distance_potential.collide(a.body, b.body, nullptr).touching;
      touching += fdem.collide(a.body, b.body, nullptr).touching;
    }
    return touching;
  };
  const int expected = 2 * static_cast<int>(pairs.size() + cubes.size());
  EXPECT_EQ(sweep(), expected);  // grows the buffers and computes the shapes' partitions
  const long before = polydem::testing::allocationCount();
  EXPECT_EQ(sweep(), expected);
  EXPECT_EQ(polydem::testing::allocationCount(), before);
}

}  // namespace
}  // namespace polydem::contact

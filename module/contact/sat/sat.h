// The separating-axis test (SAT) for two small convex polyhedra: the exact minimum penetration
// depth and its direction, in closed form, where GJK + EPA find them within a tolerance.
//
// Why it is exact: the penetration depth of A and B is the distance from the origin to the
// boundary of the Minkowski difference A - B, reached along the normal of one of its faces, and
// every face normal of A - B is a face normal of A, a face normal of B or the cross product of an
// edge of A and an edge of B (van den Bergen 2001, sec. 4.3.4; Gottschalk et al. 1996). Along
// any unit direction n the overlap
//     d(n) = max_B n . x - min_A n . x                                                     (1)
// is at least the depth, so the minimum of (1) over those candidate axes, taken in both signs, is
// the depth and its argument the direction; one axis with d < 0 proves the bodies apart. Parallel
// axes give the same d, so each body's faces and edges are taken once per direction up to sign
// (ConvexPolyhedron::axisFaces, axisEdges). Pairs of parallel edges give no axis: the faces of
// A - B they make are normal to a face of A or B (their Gauss-map arcs share a great circle).
//
// The cost is (face axes + edge axes of A x edge axes of B) projections of both bodies: 15 axes
// for two cubes. Two rectangular boxes (ConvexPolyhedron::box()) take all 15 axes the classical
// way, from the products of their rotations (sat_obb.cpp: the same answer up to round-off); other
// parallelepipeds bound their nine edge axes' overlaps from shared products and project only the
// few that could decide the answer (sat_box.cpp, the same answer bit for bit). Shapes with more
// axes keep GJK + EPA (satApplies). Costs: docs/performance.md.
#pragma once

#include "polydem/contact/contact.h"

namespace polydem::contact {

/// Upper bound on the vertex projections of one test (axes x vertices of both bodies) for
/// satApplies(): two cubes take 240, two tetrahedra 352, two triangular prisms 288.
inline constexpr int kSatMaxProjections = 1024;

/// Whether the pair is small enough for separatingAxisTest().
bool satApplies(const Body& a, const Body& b);

struct AxisTest {
  enum class Axis : std::uint8_t { kFaceA, kFaceB, kEdges };
  bool separated = false;
  /// separated: an axis n from B into A with d(n) <= 0 (A moves along it). Otherwise the unit
  /// direction of minimum overlap, from B into A.
  Vec3 normal = Vec3::UnitZ();
  double depth = 0.0;  // d(normal) > 0 when not separated
  Axis axis = Axis::kFaceA;
  int feature_a = -1, feature_b = -1;  // face (kFaceA / kFaceB) or the two edges (kEdges)
  int lowest_a = -1, highest_b = -1;   // A's vertex lowest along the normal, B's highest
};

/// The minimum of (1) over the candidate axes. `warm` (may be null) is tried first: if it
/// separates the bodies, it is returned at once. Face axes are preferred to edge axes whose
/// overlap is smaller by at most `tolerance` (a length): where an edge axis coincides with a face
/// axis (two aligned cubes) round-off must not turn a face contact into an edge contact.
/// Two rectangular boxes take the classical test (sat_obb.cpp), whose answer is
/// separatingAxisTestReference()'s up to round-off (ctest contact_sat: depths within 1e-12 of the
/// pair's size, the same axis unless two tie within that); other parallelepipeds test their nine
/// edge axes exactly only where a cheaper bound leaves it open (sat_box.cpp), bit for bit.
AxisTest separatingAxisTest(const Body& a, const Body& b, const Vec3* warm, double tolerance);

/// The same test with every axis evaluated exactly, in order: the definition of the answer, and
/// the one that separatingAxisTest() falls back to (and is checked against by ctest contact_sat).
/// Where the bodies are apart, only `separated` and `normal` are the answer; the other fields hold
/// the minimum over the axes tested before the separating one (the warm axis: the defaults).
AxisTest separatingAxisTestReference(const Body& a, const Body& b, const Vec3* warm,
                                     double tolerance);

/// For an answer on an edge-edge axis: the middle of the closest points of the two edges that
/// make it (A's at lowest_a, B's at highest_b, parallel to feature_a and feature_b), which is
/// EPA's barycentric point on crossing edges (Keissar eqs. 2.1-2.2).
Vec3 crossingPoint(const Body& a, const Body& b, const AxisTest& t);

}  // namespace polydem::contact

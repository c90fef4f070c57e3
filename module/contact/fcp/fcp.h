// Fast Common Plane (FCP) of Nezami et al. (2004), after Cundall's (1988) common plane: the plane
// between two convex polyhedra that maximises the gap between itself and the closest vertex of
// each; for overlapping blocks the gap is negative and the plane minimises the penetration.
//
// The common plane's normal n (from B into A) is one of finitely many candidates: a face normal of
// A or B, or the cross product of an edge of A and an edge of B (Nezami et al. 2004, the candidate
// planes of the 3-D FCP). With gap(n) = min_A n.a - max_B n.b, maximising the gap over these
// candidates is the separating-axis problem; the search moves from plane to plane using only the
// features at the vertices currently closest to the plane, then proves the local optimum global
// (or falls back to all candidates). docs/kernels/fcp.md describes the method and its tolerances.
#pragma once

#include "polydem/contact/contact.h"

namespace polydem::contact {

/// Tolerances of the common-plane search, as fractions of the pair's length scale
/// L = circumradius(A) + circumradius(B).
struct FcpTolerance {
  /// Vertices within this band of their body's extreme along n are "closest to the plane": they
  /// decide the contact features (1 vertex, 2 an edge, >= 3 a face) and the candidates tried next.
  static constexpr double kBand = 1e-9;
  /// A move to another candidate must raise the gap by more than this.
  static constexpr double kImprove = 1e-12;
  /// Slack of the certificate that proves a local optimum global: the penetration found is within
  /// this of the minimum. Equal to the band, within which vertices count as level anyway.
  static constexpr double kCertify = 1e-9;
};

/// Two edges whose directions make an angle with sine below this are parallel: their cross product
/// is no candidate normal.
inline constexpr double kFcpParallelSine = 1e-9;

struct FcpOptions {
  /// Stop at the first plane with a positive gap: the pair is proven separated (collide() does
  /// this). When false, the search runs to the global maximum of the gap for separated pairs too.
  bool stop_when_separated = true;
  /// Run the local search on deep overlaps too (inscribed balls overlapping), which otherwise go
  /// from the first guess straight to the exact scan. For diagnostics: how often the local search
  /// ends at a plane that is not the global optimum.
  bool always_search = false;
};

/// How a common plane was found; for tests, reports and benchmarks.
struct FcpTrace {
  bool warm = false;                // started from the caller's normal
  int moves = 0;                    // planes visited: the guess and the local moves
  int candidates = 0;               // candidate normals evaluated (search and scan)
  bool certified = false;           // the plane searched was proven optimal by the certificate
  bool full_scan = false;           // the exact scan ran (no certificate)
  bool full_scan_improved = false;  // ... and found a better plane than the search had
};

struct CommonPlane {
  Vec3 normal = Vec3::UnitZ();   // unit, from B into A
  double gap = 0.0;              // level_a - level_b; < 0: overlap, -gap is the penetration
  double level_a = 0.0;          // min over A of normal . a
  double level_b = 0.0;          // max over B of normal . b
  int vertex_a = 0;              // a vertex of A at level_a
  int vertex_b = 0;              // a vertex of B at level_b
  bool separated_early = false;  // stopped at the first positive gap (not the maximum gap)
};

/// The common plane of the pair. `warm_normal` (unit, from B into A), when given, is the start
/// plane, otherwise the plane perpendicular to the line joining the centroids. Allocation-free
/// once the calling thread's scratch buffers have grown (they are thread_local).
CommonPlane findCommonPlane(const Body& a, const Body& b, const Vec3* warm_normal,
                            const FcpOptions& options = {}, FcpTrace* trace = nullptr);

/// Contact point from the contact features of the plane (no IPM): the vertices of A within
/// FcpTolerance::kBand of level_a and those of B within the band of level_b, each a vertex, an
/// edge or a face; V-x: the vertex, E-E: the closest points of the two edges (parallel edges: the
/// middle of their overlap), E-F: the middle of the edge clipped by the face, F-F: the area
/// centroid of the intersection of the two faces projected on the plane. The point lies half way
/// between level_a and level_b. Sets `status` to kDegenerate when the features do not overlap in
/// the plane (the point then falls back to the middle of the two features).
Vec3 fcpFeaturePoint(const Body& a, const Body& b, const CommonPlane& plane, Status* status);

/// Kernel `fcp`: the common plane's normal, depth = -gap (touching only when gap < 0), the point
/// from the contact features (fcpFeaturePoint). Exact on vertex-face, crossing-edge, edge-face and
/// face-face contacts; on vertex-vertex, vertex-edge and parallel-edge contacts the plane of
/// largest gap is tilted (Keissar tables 3.1, 3.2, 3.4). Warm start: PairState::warm_direction is
/// the last common plane's normal, warm_point a point on it (the middle of the overlap).
class FcpKernel final : public Kernel {
 public:
  std::string_view name() const override { return "fcp"; }
  Contact collide(const Body& a, const Body& b, particles::PairState* state) const override;
};

/// Kernel `fcp-ipm`: the common plane's normal and depth, the point from the Intersection Polygon
/// Method (ipm.h) on the plane half way through the overlap (Keissar section 2.3). Where the
/// polygon of intersection has no area, the feature point with Status::kDegenerate.
class FcpIpmKernel final : public Kernel {
 public:
  std::string_view name() const override { return "fcp-ipm"; }
  Contact collide(const Body& a, const Body& b, particles::PairState* state) const override;
  Contact collideForSubContacts(const Body& a, const Body& b,
                                particles::PairState* state) const override;
};

}  // namespace polydem::contact

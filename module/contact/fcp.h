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

#include "contact/contact.h"

namespace polydem::contact {

/// Tolerances of the common-plane search, as fractions of the pair's length scale
/// L = circumradius(A) + circumradius(B).
struct FcpTolerance {
  /// Vertices within this band of their body's extreme along n are "closest to the plane": they
  /// decide the contact features (1 vertex, 2 an edge, >= 3 a face) and the candidates tried next.
  static constexpr double kBand = 1e-9;
  /// A move to another candidate must raise the gap by more than this.
  static constexpr double kImprove = 1e-12;
  /// Slack of the certificate that proves a local optimum global.
  static constexpr double kCertify = 1e-10;
};

/// Two edges whose directions make an angle with sine below this are parallel: their cross product
/// is no candidate normal.
inline constexpr double kFcpParallelSine = 1e-9;

struct FcpOptions {
  /// Stop at the first plane with a positive gap: the pair is proven separated (collide() does
  /// this). When false, the search runs to the global maximum of the gap for separated pairs too.
  bool stop_when_separated = true;
};

/// How a common plane was found; for tests, reports and benchmarks.
struct FcpTrace {
  bool warm = false;                // started from the caller's normal
  int moves = 0;                    // planes visited by the local search
  int candidates = 0;               // candidate normals evaluated (local search and full scan)
  bool certified = false;           // the local optimum was proven global by the certificate
  bool full_scan = false;           // all candidates were evaluated (no certificate)
  bool full_scan_improved = false;  // ... and one beat the local optimum
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

}  // namespace polydem::contact

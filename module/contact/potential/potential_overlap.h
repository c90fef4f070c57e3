// The machinery shared by the potential kernels (distance-potential, fdem): the boundary integral
// of Zhao eq. (3) over the overlap of two convex cells, each carrying a piecewise-linear potential
//
//     phi(x) = min over the cell's face planes i of d_i(x) / s_i,   d_i = inward distance to plane
//     i,
//
// (distance potential, Zhao eq. 5: s_i = r, the inradius; FDEM, Zhao eq. 1 / Munjiza: one cell per
// tetrahedron, s_i = H_i / 4). For cells A and B with overlap V and its outward normal n,
//
//     f_A = kn * integral over dV of n (phi_A - phi_B) dS                               (Zhao eq.
//     3)
//
// On the part of dV on A's surface phi_A = 0 and n is A's face normal; on B's part phi_B = 0 and n
// is B's face normal. So each face of A is clipped by B's planes (the part of A's surface inside
// B), split by B's regions {phi_B = d_j / s_j} (Zhao steps 1-2, eqs. 6-8), and the linear phi_B
// is integrated exactly over each piece by a fan of triangles (Zhao eqs. 9-12, 16-28: the integral
// of a linear function over a triangle is its area times the mean of the corner values; the first
// moment likewise); the same for B's faces inside A with phi_A.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "polydem/contact/contact.h"
#include "polydem/contact/potential/potential_cell.h"
#include "polydem/contact/potential/potential_envelope.h"
#include "polydem/core/types.h"
#include "polydem/geometry/polygon_clip.h"

namespace polydem::contact::potential {

/// Sums of the boundary integral over one or more cell pairs, in the frame the cells are given in.
struct OverlapSums {
  Vec3 force = Vec3::Zero();   // integral of n (phi_A - phi_B) dS, m^2 (times kn: N on A)
  Vec3 moment = Vec3::Zero();  // integral of x cross n (phi_A - phi_B) dS about the origin, m^3
  double phi_integral = 0.0;   // integral of (phi_A + phi_B) dS over the boundary pieces, m^2
  double area = 0.0;           // area of the boundary pieces, m^2
  // The largest boundary piece's plane (to tell a flat overlap, touching faces, from a solid one).
  double largest_piece = 0.0;
  Vec3 largest_normal = Vec3::UnitZ();
  double largest_offset = 0.0;
};

/// What one cell pair gave besides the sums.
struct PairInfo {
  bool found = false;    // some boundary piece with positive area
  double bound_a = 0.0;  // an upper bound of phi_A over the overlap
  double bound_b = 0.0;  // the same for phi_B
};

/// Integrates cell pairs. Holds reusable buffers: no allocation once they have grown.
class OverlapIntegrator {
 public:
  /// Adds the overlap of `a` and `b` (the force is on A) to `sums`, appends the corners of its
  /// boundary pieces to `corners`. Faces of either cell lying wholly outside the box [lo, hi]
  /// (which must contain the overlap) are skipped; the others are clipped by the planes of the
  /// other cell that separate their corners (B's faces only by A's planes whose faces may meet B,
  /// once A gave a piece).
  PairInfo add(const Cell& a, const Cell& b, const Vec3& lo, const Vec3& hi, OverlapSums& sums,
               std::vector<Vec3>& corners);

 private:
  struct Piece {
    int begin = 0, end = 0;  // corners in pool_ (space) and flat_pool_ (its plane)
    int plane = 0;           // the plane of its own cell it lies on
    bool on_a = true;
    PieceFrame frame;
  };
  // Whether one plane of `cell` leaves the whole box [lo, hi] outside (then there is no overlap).
  static bool excludesBox(const Cell& cell, const Vec3& lo, const Vec3& hi);
  // The other cell's planes by coordinate (plane_x_ ...), for outsideMask.
  void loadPlanes(const Cell& other);
  // Bit k set: corner v of own lies outside the other's plane k (computed once per pair).
  const std::uint64_t* outsideMask(const Cell& own, int v);
  // Appends the pieces of own's faces inside other. `usable` (or null: all): the other's planes
  // to clip by. `reaching` (or null): set to own's planes whose faces may meet the other cell.
  void clipFaces(const Cell& own, const Cell& other, bool on_a, const Vec3& lo, const Vec3& hi,
                 const std::uint64_t* usable, std::uint64_t* reaching);
  // The mean and the box of pool_ (the overlap's boundary corners), shared by both cells.
  struct PoolSummary {
    Vec3 mean, lo, hi;
  };
  PoolSummary summarisePool() const;
  // Candidates of `cell`: planes whose term can be the minimum somewhere in the overlap (a cheap
  // superset), listed and flagged per plane. Returns an upper bound of phi_cell over the overlap.
  double selectCandidates(const Cell& cell, const PoolSummary& pool, std::vector<int>& candidates,
                          std::vector<char>& is_candidate) const;

  geometry::ConvexPolygonClipper clipper_;
  EnvelopeIntegrator envelope_;
  std::vector<Vec3> pool_;
  std::vector<Vec2> flat_pool_;
  std::vector<Piece> pieces_;
  std::vector<int> candidates_a_, candidates_b_;
  std::vector<char> is_candidate_a_, is_candidate_b_;
  std::vector<std::uint64_t> outside_, all_out_, any_out_;
  std::vector<std::uint64_t> missed_, met_, reach_a_;  // per plane of a cell, as clipFaces says
  std::size_t words_ = 0;
  std::vector<char> known_;
  std::vector<double> plane_x_, plane_y_, plane_z_, plane_offset_;
};

/// The full result of a potential kernel for one pair, in world coordinates.
struct PotentialResult {
  Contact contact;
  Vec3 force = Vec3::Zero();   // integral of n (phi_A - phi_B) dS, m^2 (times the penalty: N)
  Vec3 moment = Vec3::Zero();  // its moment about the contact point, m^3
  double torsion = 0.0;        // moment.normal: the couple about the line of action, which the
                               // Contact (a force at a point) cannot carry
  double bound_a = 0.0, bound_b = 0.0;  // upper bounds of phi_A, phi_B over the overlap
};

/// Turns the sums of a pair into the Contact (Zhao eq. 29 generalised): normal = force direction,
/// potential = |force|, point = the point of the line of action half way across the overlap's
/// extent along the normal, depth = that extent. `origin` is the world point the cells' frame is
/// centred on, `length_scale` the pair's size (tolerances), `fallback_normal` the direction used
/// when the force vanishes (identical or concentric bodies: status kDegenerate).
PotentialResult finishContact(const OverlapSums& sums, std::span<const Vec3> corners,
                              const Vec3& origin, double length_scale, const Vec3& fallback_normal);

/// The common part [lo, hi] of the axis-aligned boxes of two bodies' world vertices; false if
/// the boxes are apart or only touch (no overlap volume, so no contact).
bool commonBox(std::span<const Vec3> a, std::span<const Vec3> b, Vec3& lo, Vec3& hi);

}  // namespace polydem::contact::potential

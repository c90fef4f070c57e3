// The integral of a cell's potential phi = min_j term_j (each term linear) over one boundary
// piece of the overlap, the piece split by the cell's regions {phi = term_j} (Zhao step 2, eqs.
// 7-8; docs/kernels/distance-potential.md).
//
// The piece is a convex polygon in the plane of one face, in 2D coordinates of that plane; there
// every term is an affine function of (u, v). Region k on the piece is the piece clipped by
// term_k <= term_l for the planes l that may bound k's region: its neighbours in the cell's
// nearest-face partition (geometry::FaceRegions) that are candidates of the pair when the cell
// has one, else every candidate.
// Only regions that exist are built: a walk starts at the plane smallest at the piece's centre,
// each region's polygon remembers which plane made each of its edges, and those planes are
// visited next. Where the cell's regions are located (RegionFacets), region k is clipped only by
// the neighbours whose shared facet with k meets the piece's plane: the others cannot bound
// region k in that plane. Should the walk miss a region (two bisectors meeting the piece's plane in
// one line, so that an edge carries only one of their labels), the regions' areas fall short of the
// piece's and every candidate plane gets its region built.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "polydem/contact/potential/potential_cell.h"

namespace polydem::contact::potential {

/// The plane of a piece: x = origin + u e1 + v e2 (e1, e2 orthonormal, e1 x e2 the face's
/// outward normal `normal`).
struct PieceFrame {
  Vec3 origin = Vec3::Zero();
  Vec3 e1 = Vec3::UnitX(), e2 = Vec3::UnitY();
  Vec3 normal = Vec3::UnitZ();
  Vec2 toPlane(const Vec3& x) const { return Vec2(e1.dot(x - origin), e2.dot(x - origin)); }
  Vec3 toSpace(const Vec2& y) const { return origin + y.x() * e1 + y.y() * e2; }
};

/// Integrals over one piece, in its frame.
struct PieceIntegrals {
  double integral = 0.0;      // of phi, m^2
  Vec2 first = Vec2::Zero();  // of (u, v) phi, m^3
  double area = 0.0;          // m^2
};

/// The integral of a linear function over a convex polygon (counter-clockwise) given by its
/// corner values, and its first moment (Zhao eqs. 23-25): a fan of triangles, each adding area *
/// mean value and area/12 * (sum g_i y_i + (sum g_i)(sum y_i)).
void integrateLinear(std::span<const Vec2> corners, std::span<const double> values,
                     PieceIntegrals& out);

/// Reusable buffers for splitting pieces: no allocation once they have grown.
class EnvelopeIntegrator {
 public:
  /// Adds the integral of phi_cell over the convex polygon `corners` (counter-clockwise, in
  /// `frame`), its first moment and its area. `planes` lists the cell's planes that may be the
  /// minimum somewhere in the overlap (any superset of those is right, only slower);
  /// `is_candidate[l]` is non-zero for exactly the planes l in `planes`.
  void integrate(std::span<const Vec2> corners, const PieceFrame& frame, const Cell& cell,
                 std::span<const int> planes, std::span<const char> is_candidate,
                 PieceIntegrals& out);

 private:
  // term_l(u, v) = a + g.(u, v) on the piece's plane.
  struct Term {
    double a = 0.0;
    Vec2 g = Vec2::Zero();
  };
  // Term l on this piece, made on first use (the look-up is inline: a region asks for each of
  // its neighbours' terms, most of them made already).
  const Term& term(int l) { return stamp_[l] == piece_ ? terms_[l] : makeTerm(l); }
  const Term& makeTerm(int l);
  // Region k on the piece: the piece clipped by term_k <= term_l for the planes l in `others`.
  // Returns false when nothing is left.
  bool buildRegion(int k, std::span<const int> others);
  // Which corners of region k lie (within the tolerance) on or above the piece's plane, and on
  // or below it; every bit set when the region is not located.
  struct Sides {
    std::uint64_t above = ~std::uint64_t{0}, below = ~std::uint64_t{0};
  };
  Sides sides(int k) const;
  // The planes that may bound region k: its listed neighbours, or every candidate.
  std::span<const int> others(int k) const;
  // Integrates the regions of queue_[from ..] and of the planes their edges lead to; returns the
  // area covered.
  double walk(std::size_t from, PieceIntegrals& out);
  // Grows the polygon buffers to hold n corners (they never shrink).
  void reserve(std::size_t n);
  // Keeps the part of poly_ where g.y + c <= 0; the new edge is labelled `label`. Most clips
  // cut nothing (61-83 %, docs/kernels/distance-potential.md): that test is inline, the cut not.
  bool clip(const Vec2& g, double c, int label);
  // The cut of clip(), given the corners' values in h_ and n_out > 0 of them outside.
  bool cut(std::size_t n_out, int label);

  // The piece being integrated.
  std::span<const Vec2> corners_;
  const PieceFrame* frame_ = nullptr;
  const Cell* cell_ = nullptr;
  std::span<const char> is_candidate_;
  bool skip_non_candidates_ = true;  // region k is known to meet the piece
  // The piece plane's signed distance at the cell's basis corners: h(x) = h0 + dh.(a, b, c) at
  // the point of affine coordinates (a, b, c).
  double h0_ = 0.0;
  Vec3 dh_ = Vec3::Zero();
  bool located_ = false;

  std::vector<Term> terms_;
  std::vector<std::uint64_t> stamp_;   // stamp_[l] == piece_: term l is made for this piece
  std::vector<std::uint64_t> queued_;  // queued_[l] == piece_: l is in queue_
  std::uint64_t piece_ = 0;

  std::vector<int> candidates_, queue_;
  std::vector<double> region_values_;
  // The region being built: poly_[0 .. poly_n_), labels_[i] the plane that made edge i -> i + 1.
  std::vector<Vec2> poly_, next_;
  std::vector<int> labels_, next_labels_;
  std::vector<double> h_;
  std::size_t poly_n_ = 0;
};

}  // namespace polydem::contact::potential

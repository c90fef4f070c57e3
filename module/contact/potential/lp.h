// Kernel "lp": potential blocks after Boon, Houlsby & Utili (2012), "A new algorithm for contact
// detection between convex polygonal and polyhedral particles in the discrete element method",
// Computers and Geotechnics 44, 73-82, as Keissar (2024) section 3.2 "Convex Optimization"
// benchmarks it. Formulation, parameters, cost and the cases it gets wrong: docs/kernels/lp.md.
//
// Each block is the set of its face inequalities a_i . x <= d_i (unit outward a_i, world frame).
//  1. Overlap: the Chebyshev-centre LP  minimise s  s.t.  a_i . x - s <= d_i  over the faces of
//     both blocks (geometry/small_lp.h). Its optimum s* is minus the radius of the largest ball
//     inside the overlap when the blocks overlap, and half a separating gap otherwise; the pair
//     touches iff s* < -1e-12 (r_A + r_B) (circumradii).
//  2. Point: the analytic centre of the overlap, argmax sum_i log(d_i - a_i . x) over the faces
//     of both blocks (geometry/analytic_centre.h), Newton's method started at the LP's point.
//  3. Normal: from the inner smooth potential particle of each block (Houlsby 2009, with the
//     planes moved inwards by r as Boon et al. 2012 do),
//        f_k(x) = sum_i <a_i . x - d_i + r_k>^2 - r_k^2,   <y> = max(y, 0)  (Macaulay),
//     whose level set f_k = 0 is block k with its edges and corners rounded; at the contact
//     point x_c,  n = normalise(g_B - g_A)  with g_k = grad f_k / |grad f_k| the unit outward
//     normals of the two rounded surfaces (their bisector, pointing from B into A).
//  4. Depth: the length of the overlap's chord along x_c + t n, exact from the face planes.
// r_k = KernelParams::lp_rounding * inradius of block k.
#pragma once

#include "polydem/contact/contact.h"
#include "polydem/geometry/halfspaces.h"

namespace polydem::contact {

/// grad f at x of the inner potential particle of the block whose faces are planes [begin, end)
/// of `faces`: 2 sum_i <r - s_i(x)> a_i with s_i = d_i - a_i . x (zero deeper than r inside).
Vec3 innerPotentialGradient(const geometry::Halfspaces& faces, int begin, int end, double r,
                            const Vec3& x);

/// The block's unit outward normal at x used by the kernel: grad f / |grad f|; where grad f
/// vanishes (x deeper than r below every face) its limit as r grows to reach x, the normal of
/// the nearest face (the sum over tied nearest faces). Zero only if those cancel.
Vec3 innerPotentialNormal(const geometry::Halfspaces& faces, int begin, int end, double r,
                          const Vec3& x);

class LpKernel final : public Kernel {
 public:
  /// Throws polydem::Error unless 0 < params.lp_rounding < 1.
  explicit LpKernel(const KernelParams& params = {});
  std::string_view name() const override { return "lp"; }
  Contact collide(const Body& a, const Body& b, particles::PairState* state) const override;
  double rounding() const { return rounding_; }

  /// What the last collide() on this thread did (read by tests and benchmarks).
  struct Trace {
    bool spheres_apart = false;      // rejected by the bounding spheres
    bool warm_axis = false;          // rejected by the last separating direction
    bool warm_point = false;         // the stored contact point was inside both: no LP solved
    bool centre_line = false;        // the chord of the line of centres gave the start: no LP
    bool centre_line_apart = false;  // the line of centres separates the vertices: no LP
    bool lp_solved = false;
    bool lp_warm_basis = false;  // the LP was offered the stored basis
    int lp_pivots = 0;
    double lp_objective = 0.0;  // s*
    int newton_iterations = 0;
    double newton_decrement = 0.0;
    bool newton_converged = false;
  };
  static const Trace& lastTrace();

 private:
  double rounding_;
};

}  // namespace polydem::contact

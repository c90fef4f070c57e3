// The FDEM potential contact kernel (Munjiza 2004; Zhao et al. section 2, eqs. 1-3), the baseline
// of the distance potential: each tetrahedron carries phi(x) = min over its faces of 4 V_i(x) / V
// = d_i(x) / (H_i / 4) (1 at its centroid, 0 on its faces). A tetrahedral body is one element; any
// other polyhedron is split from its centroid into tetrahedra, one per face triangle (polygonal
// faces fanned from their centroid). The force on A is penalty * the sum over all tetrahedron
// pairs of the integral over their overlap's boundary of n (phi_A - phi_B) dS (Zhao eq. 3).
// See docs/kernels/fdem.md.
#pragma once

#include "polydem/contact/contact.h"
#include "polydem/contact/potential/potential_overlap.h"

namespace polydem::contact {

class FdemKernel final : public Kernel {
 public:
  std::string_view name() const override { return "fdem"; }
  /// model kPotential; the same outputs as the distance-potential kernel (no inner domain: the
  /// FDEM potential is defined everywhere). `state` is not used.
  Contact collide(const Body& a, const Body& b, particles::PairState* state) const override;
  /// The same, with the force vector, its moment about the point and the dropped torsion.
  potential::PotentialResult evaluate(const Body& a, const Body& b) const;
};

}  // namespace polydem::contact

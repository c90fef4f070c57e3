// The distance-potential contact kernel of Zhao et al. (sections 3.1-3.2): each polyhedron carries
// phi(x) = (distance from x to its surface) / r, r its inscribed-sphere radius (Zhao eq. 5), and
// the normal force on A is penalty * integral over the overlap's boundary of n (phi_A - phi_B) dS
// (Zhao eqs. 3, 13). See docs/kernels/distance-potential.md.
#pragma once

#include "polydem/contact/contact.h"
#include "polydem/contact/potential/potential_overlap.h"

namespace polydem::contact {

class DistancePotentialKernel final : public Kernel {
 public:
  std::string_view name() const override { return "distance-potential"; }
  /// model kPotential; potential = |integral| (m^2); normal = the force's direction on A; point =
  /// on the line of action, half way across the overlap along the normal; depth = the overlap's
  /// extent along the normal. Status kInnerDomainReached when the overlap reaches a point at
  /// distance r from every face of A or of B (the force is still returned); kDegenerate when the
  /// force vanishes (identical or concentric bodies). `state` is not used.
  Contact collide(const Body& a, const Body& b, particles::PairState* state) const override;
  /// The same, with the force vector, its moment about the point and the torsion the Contact
  /// drops (tests, reports).
  potential::PotentialResult evaluate(const Body& a, const Body& b) const;
};

}  // namespace polydem::contact

// Kernels `gjk-epa` and `gjk-epa-ipm` (Keissar chapters 2-3).
//
// gjk-epa: GJK decides overlap on A - B (gjk.h), EPA finds the minimum penetration depth and its
// direction (epa.h); the point is EPA's barycentric point (Keissar eqs. 2.1-2.2), off the centre of
// the patch on face-face, edge-face and parallel-edge contacts, as the thesis reports.
// gjk-epa-ipm: the same normal and depth, the point replaced by the Intersection Polygon Method
// (ipm.h) on the plane half way through the overlap along EPA's normal (Keissar section 2.3).
//
// Both give the minimum translation direction: on vertex-vertex, vertex-edge and parallel-edge
// contacts that is not the vertical of BENCHMARKS.md C (Keissar tables 3.1, 3.2, 3.4).
// Warm start: PairState::warm_direction holds the last separating axis or contact normal.
//
// Small shapes (sat.h: two cubes, tetrahedra, prisms) skip GJK + EPA in gjk-epa-ipm and in both
// kernels under sub-contacts: the separating-axis test gives the exact minimum-overlap direction
// and depth where EPA gives them within its tolerance, and the point of the vertex-face contact
// that direction stands for. GJK + EPA run for larger shapes.
#pragma once

#include "polydem/contact/contact.h"

namespace polydem::contact {

/// GJK + EPA on the pair; `state` (may be null) is read for and updated with the warm start.
/// Tolerances are RelTol::kIteration times the sum of the circumradii. For a touching contact,
/// `extremes` (may be null) receives A's vertex lowest and B's vertex highest along the normal.
struct Extremes {
  int lowest_a = -1, highest_b = -1;
};
Contact gjkEpaContact(const Body& a, const Body& b, particles::PairState* state,
                      Extremes* extremes = nullptr);

class GjkEpaKernel final : public Kernel {
 public:
  explicit GjkEpaKernel(bool separating_axes = true) : separating_axes_(separating_axes) {}
  std::string_view name() const override { return "gjk-epa"; }
  Contact collide(const Body& a, const Body& b, particles::PairState* state) const override;
  /// For small shapes the separating-axis test's exact answer (sat.h) where it is a face axis,
  /// else collide()'s; sub-contacts replace the point of face contacts, so EPA's barycentric
  /// point, the reason for this kernel, is not needed there.
  Contact collideForSubContacts(const Body& a, const Body& b,
                                particles::PairState* state) const override;

 private:
  bool separating_axes_;  // KernelParams::separating_axes
};

class GjkEpaIpmKernel final : public Kernel {
 public:
  explicit GjkEpaIpmKernel(bool separating_axes = true) : separating_axes_(separating_axes) {}
  std::string_view name() const override { return "gjk-epa-ipm"; }
  /// EPA's (or, for small shapes, the separating-axis test's) contact with the point from the
  /// IPM; where the polygon of intersection has no area
  /// (touching features), EPA's point with Status::kDegenerate.
  Contact collide(const Body& a, const Body& b, particles::PairState* state) const override;
  Contact collideForSubContacts(const Body& a, const Body& b,
                                particles::PairState* state) const override;

 private:
  bool separating_axes_;  // KernelParams::separating_axes
};

}  // namespace polydem::contact

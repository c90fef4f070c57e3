#include "polydem/contact/gjk/gjk_epa.h"

#include "polydem/contact/gjk/epa.h"
#include "polydem/contact/gjk/gjk.h"
#include "polydem/contact/kernel_factories.h"
#include "polydem/contact/point/ipm.h"
#include "polydem/contact/sat/sat.h"
#include "polydem/contact/sat/sat_detail.h"
#include "polydem/contact/support.h"
#include "polydem/core/tolerance.h"

namespace polydem::contact {

Contact gjkEpaContact(const Body& a, const Body& b, particles::PairState* state,
                      Extremes* extremes) {
  const double tolerance = absTol(pairLengthScale(a, b), RelTol::kIteration);
  const bool warm =
      state != nullptr && state->warm_valid != 0 && state->warm_direction.squaredNorm() > 0.0;
  const Vec3 axis = warm ? state->warm_direction : Vec3(a.centroid() - b.centroid());
  MinkowskiSupport support(a, b);
  const GjkResult gjk = gjkIntersect(support, axis, tolerance);
  Contact c;
  if (gjk.separated) {
    if (state != nullptr) {
      state->warm_direction = gjk.axis;
      state->warm_valid = 1;
    }
    return c;
  }
  const EpaResult epa = epaPenetration(support, gjk.simplex, tolerance);
  if (!epa.touching) return c;  // touching without depth; the warm start is kept as it was
  c.touching = true;
  c.normal = epa.normal;
  c.depth = epa.depth;
  c.point = epa.point;
  c.status = (gjk.converged && epa.converged) ? Status::kOk : Status::kNotConverged;
  if (state != nullptr) {
    state->warm_direction = epa.normal;
    state->warm_valid = 1;
  }
  if (extremes != nullptr) *extremes = {epa.lowest_a, epa.highest_b};
  return c;
}

namespace {

// The answer for small shapes (sat.h), false for larger ones: the exact minimum-overlap direction
// and depth from the separating-axis test. The point is EPA's for the contact the axis stands for
// (Keissar eqs. 2.1-2.2): on a face axis, the vertex-face contact's (the other body's deepest
// vertex moved half the depth back along the normal); on an edge-edge axis, the crossing edges'
// (the middle of their closest points). Face-face and edge-face contacts take their point from
// the IPM or their sub-contacts. Inline, two boxes straight to their test (the first branch of
// both satApplies() and separatingAxisTest()), and the contact written into `c`, the caller's
// default-constructed result, so that the call chain from the kernel's entry to the box test
// stays short on the dense pack's hot path (docs/performance.md). `extremes` may be null.
[[gnu::always_inline]] inline bool satContact(const Body& a, const Body& b,
                                              particles::PairState* state, Contact& c,
                                              Extremes* extremes) {
  const bool boxes = a.shape->box() != nullptr && b.shape->box() != nullptr;
  if (!boxes && !satApplies(a, b)) return false;
  const double tolerance = absTol(pairLengthScale(a, b), RelTol::kIteration);
  const bool warm = state != nullptr && state->warm_valid != 0;
  const Vec3* warm_axis = warm ? &state->warm_direction : nullptr;
  const AxisTest sat = boxes ? sat_detail::boxTest(a, b, warm_axis, tolerance)
                             : separatingAxisTest(a, b, warm_axis, tolerance);
  if (state != nullptr) {
    state->warm_direction = sat.normal;
    state->warm_valid = 1;
  }
  if (sat.separated) return true;
  c.touching = true;
  c.normal = sat.normal;
  c.depth = sat.depth;
  switch (sat.axis) {
    case AxisTest::Axis::kFaceA:
      c.point = b.vertices[sat.highest_b] - (0.5 * sat.depth) * sat.normal;
      break;
    case AxisTest::Axis::kFaceB:
      c.point = a.vertices[sat.lowest_a] + (0.5 * sat.depth) * sat.normal;
      break;
    case AxisTest::Axis::kEdges:
      c.point = crossingPoint(a, b, sat);
      break;
  }
  if (extremes != nullptr) *extremes = {sat.lowest_a, sat.highest_b};
  return true;
}

}  // namespace

Contact GjkEpaKernel::collide(const Body& a, const Body& b, particles::PairState* state) const {
  return gjkEpaContact(a, b, state);
}

// One named result on every path, so that it is built in the caller's (no copy).
Contact GjkEpaKernel::collideForSubContacts(const Body& a, const Body& b,
                                            particles::PairState* state) const {
  Contact c;
  if (!separating_axes_ || !satContact(a, b, state, c, nullptr)) c = gjkEpaContact(a, b, state);
  return c;
}

Contact GjkEpaIpmKernel::collide(const Body& a, const Body& b, particles::PairState* state) const {
  Extremes extremes;
  Contact c;
  if (!separating_axes_ || !satContact(a, b, state, c, &extremes)) {
    c = gjkEpaContact(a, b, state, &extremes);
  }
  if (!c.touching) return c;
  // EPA's last support query already found the extremes of the overlap along its normal.
  const Vec3 plane_point = extremes.lowest_a >= 0
                               ? midOverlapPoint(a.vertices[extremes.lowest_a],
                                                 b.vertices[extremes.highest_b], c.normal, c.point)
                               : midOverlapPoint(a, b, c.normal, c.point);
  const auto polygon = intersectionPolygon(a, b, c.normal, plane_point);
  if (polygon) {
    c.point = polygon->centroid;
  } else if (c.status == Status::kOk) {
    c.status = Status::kDegenerate;
  }
  return c;
}

Contact GjkEpaIpmKernel::collideForSubContacts(const Body& a, const Body& b,
                                               particles::PairState* state) const {
  Contact c;
  // No IPM: sub-contacts place the force on faces.
  if (!separating_axes_ || !satContact(a, b, state, c, nullptr)) c = gjkEpaContact(a, b, state);
  return c;
}

std::unique_ptr<Kernel> makeGjkEpa(const KernelParams& params) {
  return std::make_unique<GjkEpaKernel>(params.separating_axes);
}

std::unique_ptr<Kernel> makeGjkEpaIpm(const KernelParams& params) {
  return std::make_unique<GjkEpaIpmKernel>(params.separating_axes);
}

}  // namespace polydem::contact

#include "polydem/contact/gjk_epa.h"

#include "polydem/contact/epa.h"
#include "polydem/contact/gjk.h"
#include "polydem/contact/ipm.h"
#include "polydem/contact/kernel_factories.h"
#include "polydem/contact/support.h"
#include "polydem/core/tolerance.h"

namespace polydem::contact {

Contact gjkEpaContact(const Body& a, const Body& b, PairState* state, Extremes* extremes) {
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

Contact GjkEpaKernel::collide(const Body& a, const Body& b, PairState* state) const {
  return gjkEpaContact(a, b, state);
}

Contact GjkEpaIpmKernel::collide(const Body& a, const Body& b, PairState* state) const {
  Extremes extremes;
  Contact c = gjkEpaContact(a, b, state, &extremes);
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
                                               PairState* state) const {
  return gjkEpaContact(a, b, state, nullptr);  // no IPM: sub-contacts place the force on faces
}

std::unique_ptr<Kernel> makeGjkEpa(const KernelParams&) {
  return std::make_unique<GjkEpaKernel>();
}

std::unique_ptr<Kernel> makeGjkEpaIpm(const KernelParams&) {
  return std::make_unique<GjkEpaIpmKernel>();
}

}  // namespace polydem::contact

// Kernels `fcp` and `fcp-ipm`: the common plane (fcp_search.cpp) and the contact point from the
// contact features (fcp_point.cpp) or from the Intersection Polygon Method (ipm.h).
#include "polydem/contact/fcp/fcp.h"

#include "polydem/contact/kernel_factories.h"
#include "polydem/contact/point/ipm.h"

namespace polydem::contact {

namespace {

/// The common plane of the pair, warm-started from and written back to `state`. Returns false
/// when the pair is not touching (bounding spheres apart, or gap >= 0).
bool commonPlane(const Body& a, const Body& b, particles::PairState* state, CommonPlane& plane) {
  // Bounding spheres about the centroids: far pairs cost two centroids and no support query.
  const Vec3 between = a.centroid() - b.centroid();
  const double reach = a.circumradius() + b.circumradius();
  if (between.squaredNorm() > reach * reach) return false;
  const bool warm = state != nullptr && state->warm_valid != 0;
  plane = findCommonPlane(a, b, warm ? &state->warm_direction : nullptr);
  if (state != nullptr) {
    state->warm_direction = plane.normal;
    state->warm_point =
        a.vertices[plane.vertex_a] + 0.5 * (plane.level_b - plane.level_a) * plane.normal;
    state->warm_valid = 1;
  }
  return plane.gap < 0.0;
}

Contact touching(const CommonPlane& plane) {
  Contact c;
  c.touching = true;
  c.normal = plane.normal;
  c.depth = -plane.gap;
  return c;
}

}  // namespace

Contact FcpKernel::collide(const Body& a, const Body& b, particles::PairState* state) const {
  CommonPlane plane;
  if (!commonPlane(a, b, state, plane)) return {};
  Contact c = touching(plane);
  c.point = fcpFeaturePoint(a, b, plane, &c.status);
  return c;
}

Contact FcpIpmKernel::collide(const Body& a, const Body& b, particles::PairState* state) const {
  CommonPlane plane;
  if (!commonPlane(a, b, state, plane)) return {};
  Contact c = touching(plane);
  // The mid-overlap plane, through a point level with the closest vertex of A plus half the depth.
  const Vec3 on_plane = a.vertices[plane.vertex_a] + 0.5 * c.depth * plane.normal;
  if (const auto polygon = intersectionPolygon(a, b, plane.normal, on_plane)) {
    c.point = polygon->centroid;
  } else {
    c.point = fcpFeaturePoint(a, b, plane, &c.status);
    c.status = Status::kDegenerate;
  }
  return c;
}

Contact FcpIpmKernel::collideForSubContacts(const Body& a, const Body& b,
                                            particles::PairState* state) const {
  // No IPM: sub-contacts place the force on faces and edges; fcp's own point serves the rest.
  CommonPlane plane;
  if (!commonPlane(a, b, state, plane)) return {};
  Contact c = touching(plane);
  c.point = fcpFeaturePoint(a, b, plane, &c.status);
  return c;
}

std::unique_ptr<Kernel> makeFcp(const KernelParams&) {
  return std::make_unique<FcpKernel>();
}

std::unique_ptr<Kernel> makeFcpIpm(const KernelParams&) {
  return std::make_unique<FcpIpmKernel>();
}

}  // namespace polydem::contact

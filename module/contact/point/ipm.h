// The Intersection Polygon Method (Keissar section 2.3): the contact point as the area centroid of
// the polygon in which the plane of contact cuts the overlap of A and B, i.e. the intersection of
// the two section polygons. Any kernel that knows a contact normal can use it (gjk-epa-ipm,
// fcp-ipm).
#pragma once

#include <optional>

#include "polydem/contact/contact.h"

namespace polydem::contact {

/// The polygon of intersection in the plane of contact.
struct IntersectionPolygon {
  Vec3 centroid = Vec3::Zero();  // area centroid, on the plane (Keissar eqs. 2.17-2.19)
  double area = 0.0;
  int corners = 0;
};

/// The centroid of the intersection of A's and B's sections by the plane through `plane_point`
/// with unit normal `normal`: A's section polygon (Keissar eqs. 2.3-2.7) clipped by the traces of
/// B's faces (eqs. 2.8-2.16; see geometry/polygon.h), then its area centroid (eqs. 2.17-2.19).
/// Nothing when the plane misses either body or the intersection has no area: width below 1e-12
/// of the pair's size (sum of circumradii), as for exactly touching features. Put `plane_point`
/// near the contact: 2D coordinates are taken relative to it. No heap allocation once warm
/// (thread_local scratch buffers: polydem runs one thread per rank).
std::optional<IntersectionPolygon> intersectionPolygon(const Body& a, const Body& b,
                                                       const Vec3& normal, const Vec3& plane_point);

/// The point of the plane with unit normal `normal` (from B into A) half way through the overlap
/// along it, offset (min over A of n . a + max over B of n . b) / 2, nearest to `near`.
Vec3 midOverlapPoint(const Body& a, const Body& b, const Vec3& normal, const Vec3& near);
/// The same from A's lowest and B's highest point along the normal, when they are known already.
Vec3 midOverlapPoint(const Vec3& lowest_a, const Vec3& highest_b, const Vec3& normal,
                     const Vec3& near);

/// Both steps: the IPM contact point for a contact normal, with the plane in the middle of the
/// overlap along it; `near` is any point near the contact (e.g. another kernel's point).
std::optional<IntersectionPolygon> ipmContact(const Body& a, const Body& b, const Vec3& normal,
                                              const Vec3& near);

}  // namespace polydem::contact

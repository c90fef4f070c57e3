#include "polydem/contact/point/ipm.h"

#include <algorithm>
#include <vector>

#include "polydem/contact/support.h"
#include "polydem/core/tolerance.h"
#include "polydem/geometry/plane_section.h"
#include "polydem/geometry/polygon.h"

namespace polydem::contact {

namespace {

/// Reused buffers: they grow to the largest section seen and are never freed, so a warm thread
/// allocates nothing.
struct IpmScratch {
  std::vector<double> heights_a, heights_b;
  std::vector<Vec2> points, section, clipped, spare;
  std::vector<geometry::HalfPlane> half_planes;
};

IpmScratch& ipmScratch() {
  thread_local IpmScratch s;
  return s;
}

/// Width below which (relative to the pair's size) a polygon of intersection has no area.
constexpr double kDegenerateWidth = RelTol::kIteration;

}  // namespace

std::optional<IntersectionPolygon> intersectionPolygon(const Body& a, const Body& b,
                                                       const Vec3& normal,
                                                       const Vec3& plane_point) {
  IpmScratch& s = ipmScratch();
  const geometry::PlaneFrame frame = geometry::PlaneFrame::make(normal, plane_point);
  geometry::planeHeights(b.vertices, frame, s.heights_b);
  if (!geometry::sectionHalfPlanes(*b.shape, b.vertices, b.rotation, frame, s.heights_b,
                                   s.half_planes)) {
    return std::nullopt;
  }
  geometry::planeHeights(a.vertices, frame, s.heights_a);
  geometry::sectionPolygon(*a.shape, a.vertices, frame, s.heights_a, s.section, s.points);
  if (s.section.size() < 3) return std::nullopt;
  geometry::clipByHalfPlanes(s.section, s.half_planes, s.clipped, s.spare);
  const geometry::AreaCentroid m = geometry::areaCentroid(s.clipped);
  const double size = pairLengthScale(a, b);
  if (!(m.area > kDegenerateWidth * size * m.extent)) return std::nullopt;
  return IntersectionPolygon{frame.lift(m.centroid), m.area, static_cast<int>(s.clipped.size())};
}

Vec3 midOverlapPoint(const Vec3& lowest_a, const Vec3& highest_b, const Vec3& normal,
                     const Vec3& near) {
  // Heights relative to `near`, so that coordinates far from the origin lose no accuracy.
  const double offset = 0.5 * (normal.dot(lowest_a - near) + normal.dot(highest_b - near));
  return near + offset * normal;
}

Vec3 midOverlapPoint(const Body& a, const Body& b, const Vec3& normal, const Vec3& near) {
  return midOverlapPoint(a.vertices[supportIndex(a, -normal)], b.vertices[supportIndex(b, normal)],
                         normal, near);
}

std::optional<IntersectionPolygon> ipmContact(const Body& a, const Body& b, const Vec3& normal,
                                              const Vec3& near) {
  return intersectionPolygon(a, b, normal, midOverlapPoint(a, b, normal, near));
}

}  // namespace polydem::contact

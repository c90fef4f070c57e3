// ConvexPolyhedron::fromPoints: point cloud -> convex polyhedron with true polygon faces.
//
// 1. The cloud is checked (point_cloud_checks.h) and moved to unit size: centred on its bounding
//    box and scaled by a power of two (exact), so every tolerance below is relative.
// 2. Qhull gives the hull facets; facets coplanar to round-off are already merged by qhull.
// 3. Facets whose vertices lie within RelTol::kPlane of a common plane are grown into one face
//    (region growing from the largest facet, the plane refitted as faces grow). Merging within a
//    tolerance is not transitive: on adversarial input (surfaces wavy at the tolerance scale) a
//    grown face can come out non-convex. Every face set is therefore checked (strictly convex
//    faces, each edge shared by two opposite faces, Euler characteristic 2) and, if it fails,
//    rebuilt with a smaller merge tolerance, down to qhull's own round-off merges.
// 4. A hull vertex is a corner of the polyhedron if it touches at least three faces. Points on an
//    edge touch two faces, points inside a face one: they are dropped. The rule is combinatorial,
//    so neighbouring faces agree on the ends of their common edge (the check of step 3 confirms).
// 5. Each face lists its corners counter-clockwise about its outward normal; faces and vertices get
//    a canonical order (vertices by input index, faces by their smallest vertex list).
#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <numeric>
#include <tuple>
#include <utility>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/core/tolerance.h"
#include "polydem/geometry/convex_polyhedron.h"
#include "polydem/geometry/point_cloud_checks.h"
#include "polydem/geometry/qhull_facets.h"

namespace polydem::geometry {

namespace {

/// `ids` (indices into `points`) sorted counter-clockwise about `normal` around their mean.
/// Exact for the corners of a convex polygon, whatever its shape, as the mean is inside it.
void sortCounterClockwise(std::vector<int>& ids, const std::vector<Vec3>& points,
                          const Vec3& normal) {
  Vec3 mean = Vec3::Zero();
  for (int i : ids) mean += points[i];
  mean /= static_cast<double>(ids.size());
  const Vec3 u = normal.unitOrthogonal();
  const Vec3 w = normal.cross(u);
  std::vector<std::pair<double, int>> keyed;
  keyed.reserve(ids.size());
  for (int i : ids) {
    const Vec3 d = points[i] - mean;
    keyed.emplace_back(std::atan2(d.dot(w), d.dot(u)), i);
  }
  std::sort(keyed.begin(), keyed.end());
  for (std::size_t k = 0; k < ids.size(); ++k) ids[k] = keyed[k].second;
}

/// Area and area centroid of a polygon whose corners are ordered about `normal`.
std::pair<double, Vec3> polygonArea(const std::vector<int>& ids, const std::vector<Vec3>& points,
                                    const Vec3& normal) {
  const Vec3& o = points[ids[0]];
  double area = 0.0;
  Vec3 moment = Vec3::Zero();
  for (std::size_t k = 1; k + 1 < ids.size(); ++k) {
    const Vec3& b = points[ids[k]];
    const Vec3& c = points[ids[k + 1]];
    const double a = 0.5 * (b - o).cross(c - o).dot(normal);
    area += a;
    moment += a * (o + b + c) / 3.0;
  }
  return {area, area > 0.0 ? Vec3(moment / area) : o};
}

struct FacetInfo {
  double area = 0.0;
  Vec3 centroid;
};

std::vector<FacetInfo> facetInfo(const std::vector<QhullFacet>& facets,
                                 const std::vector<Vec3>& unit) {
  std::vector<FacetInfo> info(facets.size());
  for (std::size_t f = 0; f < facets.size(); ++f) {
    std::vector<int> ids = facets[f].points;
    sortCounterClockwise(ids, unit, facets[f].normal);
    std::tie(info[f].area, info[f].centroid) = polygonArea(ids, unit, facets[f].normal);
  }
  return info;
}

/// Step 3: face index of every qhull facet, faces grown from the largest unassigned facet.
std::vector<int> growFaces(const std::vector<QhullFacet>& facets,
                           const std::vector<FacetInfo>& info, const std::vector<Vec3>& unit,
                           double tol, std::vector<Vec3>& face_normals) {
  std::vector<int> order(facets.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return info[a].area > info[b].area; });
  face_normals.clear();
  std::vector<int> face_of(facets.size(), -1);
  for (int seed : order) {
    if (face_of[seed] >= 0) continue;
    const int face = static_cast<int>(face_normals.size());
    face_of[seed] = face;
    Vec3 normal = facets[seed].normal;
    double offset = facets[seed].offset;
    Vec3 normal_sum = info[seed].area * normal;
    Vec3 moment_sum = info[seed].area * info[seed].centroid;
    double area_sum = info[seed].area;
    std::deque<int> queue{seed};
    while (!queue.empty()) {
      const int f = queue.front();
      queue.pop_front();
      for (int g : facets[f].neighbours) {
        if (face_of[g] >= 0) continue;
        const bool coplanar =
            std::all_of(facets[g].points.begin(), facets[g].points.end(),
                        [&](int p) { return std::abs(normal.dot(unit[p]) - offset) <= tol; });
        if (!coplanar) continue;
        face_of[g] = face;
        queue.push_back(g);
        // Refit the plane: area-weighted normal through the area centroid.
        normal_sum += info[g].area * facets[g].normal;
        moment_sum += info[g].area * info[g].centroid;
        area_sum += info[g].area;
        normal = normal_sum.normalized();
        offset = normal.dot(moment_sum / area_sum);
      }
    }
    face_normals.push_back(normal);
  }
  return face_of;
}

/// Faces as lists of input point indices, and the corners (input indices, ascending).
struct FaceSet {
  std::vector<int> corners;
  std::vector<std::vector<int>> faces;
};

/// Whether the polygons make a closed polyhedron with strictly convex faces: every corner turns
/// left about the face's own (Newell) normal by clearly more than round-off, every directed edge
/// appears once and its reverse in another face, and V - E + F = 2.
bool isConsistent(const FaceSet& set, const std::vector<Vec3>& unit) {
  // sin of the smallest turn at a corner; below it the corner is straight to round-off (its two
  // neighbouring faces are then coplanar to about this much, and should have been merged).
  constexpr double kMinTurn = 1e-12;
  std::vector<std::pair<int, int>> directed;
  for (const auto& face : set.faces) {
    const std::size_t n = face.size();
    if (n < 3) return false;
    Vec3 newell = Vec3::Zero();
    for (std::size_t i = 0; i < n; ++i) newell += unit[face[i]].cross(unit[face[(i + 1) % n]]);
    const Vec3 normal = newell.normalized();
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 ab = unit[face[(i + 1) % n]] - unit[face[i]];
      const Vec3 bc = unit[face[(i + 2) % n]] - unit[face[(i + 1) % n]];
      if (!(ab.cross(bc).dot(normal) > kMinTurn * ab.norm() * bc.norm())) return false;
      directed.emplace_back(face[i], face[(i + 1) % n]);
    }
  }
  std::sort(directed.begin(), directed.end());
  for (std::size_t k = 0; k < directed.size(); ++k) {
    if (k > 0 && directed[k] == directed[k - 1]) return false;
    const std::pair<int, int> reverse{directed[k].second, directed[k].first};
    if (!std::binary_search(directed.begin(), directed.end(), reverse)) return false;
  }
  const std::size_t v = set.corners.size(), e = directed.size() / 2, f = set.faces.size();
  return v + f == e + 2;
}

/// Step 4: corners (hull vertices on at least three faces) and the faces through them.
FaceSet facesFromGroups(const std::vector<QhullFacet>& facets, const std::vector<int>& face_of,
                        const std::vector<Vec3>& face_normals, const std::vector<Vec3>& unit) {
  std::vector<std::vector<int>> faces_at(unit.size());
  for (std::size_t f = 0; f < facets.size(); ++f) {
    for (int p : facets[f].points) faces_at[p].push_back(face_of[f]);
  }
  FaceSet set;
  set.faces.resize(face_normals.size());
  for (std::size_t p = 0; p < unit.size(); ++p) {
    auto& at = faces_at[p];
    std::sort(at.begin(), at.end());
    at.erase(std::unique(at.begin(), at.end()), at.end());
    if (at.size() < 3) continue;
    set.corners.push_back(static_cast<int>(p));
    for (int f : at) set.faces[f].push_back(static_cast<int>(p));
  }
  for (std::size_t f = 0; f < set.faces.size(); ++f) {
    if (set.faces[f].size() >= 3) sortCounterClockwise(set.faces[f], unit, face_normals[f]);
  }
  return set;
}

/// Step 5: vertex lists rotated to start at their smallest index, faces sorted.
void canonicalise(std::vector<std::vector<int>>& faces) {
  for (auto& face : faces) {
    std::rotate(face.begin(), std::min_element(face.begin(), face.end()), face.end());
  }
  std::sort(faces.begin(), faces.end());
}

/// The hull's least width over its face directions: the smallest depth, below a face, of the
/// vertex deepest below it. Each face's deepest vertex is found by climbing the vertex graph
/// (supportIndex), which ends at the same vertex from any start; the faces are visited
/// breadth-first across their edges and each climb starts from the deepest vertex of the face
/// it was reached from, which lies near its own, so the climbs are short even on a hull of 10^5
/// faces (a climb from the face's own vertex crosses the whole hull).
double leastWidth(const ConvexPolyhedron& poly) {
  const auto& faces = poly.faces();
  const auto& edges = poly.edges();
  std::vector<int> deepest(faces.size(), -1);
  double width = std::numeric_limits<double>::infinity();
  for (std::size_t root = 0; root < faces.size(); ++root) {  // one tree: the hull is connected
    if (deepest[root] >= 0) continue;
    std::deque<std::pair<int, int>> queue{{static_cast<int>(root), faces[root].vertices[0]}};
    deepest[root] = faces[root].vertices[0];
    while (!queue.empty()) {
      const auto [f, hint] = queue.front();
      queue.pop_front();
      const Face& face = faces[f];
      deepest[f] = poly.supportIndex(-face.normal, hint);
      width = std::min(width, face.offset - face.normal.dot(poly.vertices()[deepest[f]]));
      for (int e : face.edges) {
        const int g = edges[e].f0 == f ? edges[e].f1 : edges[e].f0;
        if (deepest[g] >= 0) continue;
        deepest[g] = deepest[f];  // queued; its own climb starts here
        queue.emplace_back(g, deepest[f]);
      }
    }
  }
  return width;
}

}  // namespace

ConvexPolyhedron ConvexPolyhedron::fromPoints(std::span<const Vec3> points, BuildReport* report) {
  const CloudFrame frame = checkPointCloud(points);
  int exponent = 0;
  std::frexp(frame.size, &exponent);
  std::vector<Vec3> unit(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3 d = points[i] - frame.centre;
    for (int k = 0; k < 3; ++k) unit[i][k] = std::ldexp(d[k], -exponent);
  }
  const double unit_size = std::ldexp(frame.size, -exponent);  // in [0.5, 1)
  const double tol = absTol(unit_size, RelTol::kPlane);

  const std::vector<QhullFacet> facets = qhullFacets(unit);
  const std::vector<FacetInfo> info = facetInfo(facets, unit);
  FaceSet set;
  bool consistent = false;
  for (double factor : {1.0, 1e-2, 1e-4, 0.0}) {
    std::vector<Vec3> face_normals;
    const std::vector<int> face_of = growFaces(facets, info, unit, factor * tol, face_normals);
    set = facesFromGroups(facets, face_of, face_normals, unit);
    consistent = isConsistent(set, unit);
    if (consistent) break;
  }
  if (!consistent) {
    throw GeometryError("convex hull of " + std::to_string(points.size()) +
                        " points: no consistent polygon faces (input degenerate at round-off?)");
  }
  std::vector<int> vertex_of_point(points.size(), -1);
  for (std::size_t i = 0; i < set.corners.size(); ++i) {
    vertex_of_point[set.corners[i]] = static_cast<int>(i);
  }
  std::vector<std::vector<int>> faces = std::move(set.faces);
  for (auto& face : faces) {
    for (int& p : face) p = vertex_of_point[p];
  }
  canonicalise(faces);
  const std::vector<int>& corners = set.corners;

  std::vector<Vec3> vertices;
  vertices.reserve(corners.size());
  for (int p : corners) vertices.push_back(points[p]);
  ConvexPolyhedron poly;
  poly.buildTopology(vertices, faces);

  // The least-squares flatness check cannot see every thin cloud; the hull can: its width is at
  // most the largest depth of the vertices below any one face.
  const double size_tol = absTol(frame.size, RelTol::kPlane);
  const double width = leastWidth(poly);
  if (width <= size_tol) {
    throw GeometryError(cat("flat point cloud: the hull of ", points.size(), " points is only ",
                            width, " thick, less than ", RelTol::kPlane, " of the cloud size ",
                            frame.size));
  }
  poly.computeMassProperties();
  poly.computeRadii();

  if (report) {
    *report = BuildReport{};
    report->vertex_of_input = corners;
    for (std::size_t p = 0; p < points.size(); ++p) {
      if (vertex_of_point[p] >= 0) continue;
      double outside = -std::numeric_limits<double>::infinity();
      for (const Face& face : poly.faces_) {
        outside = std::max(outside, face.normal.dot(points[p]) - face.offset);
      }
      auto& list = outside >= -size_tol ? report->boundary_points : report->interior_points;
      list.push_back(static_cast<int>(p));
    }
  }
  return poly;
}

}  // namespace polydem::geometry

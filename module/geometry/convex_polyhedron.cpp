// ConvexPolyhedron: topology (faces, edges, adjacency), support mapping and rigid motions.
// Building from points is in convex_hull.cpp, mass properties in mass_properties.cpp, plane
// splits in polyhedron_split.cpp.
#include "polydem/geometry/convex_polyhedron.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>

#include "polydem/core/error.h"
#include "polydem/core/strings.h"
#include "polydem/geometry/distinct_directions.h"

namespace polydem::geometry {

namespace {

/// Outward normal, area and area centroid of a polygon from its counter-clockwise corners, by the
/// fan about the corners' mean (Newell's normal; exact for planar polygons).
void fillFaceGeometry(Face& face, const std::vector<Vec3>& vertices) {
  Vec3 mean = Vec3::Zero();
  for (int v : face.vertices) mean += vertices[v];
  mean /= static_cast<double>(face.vertices.size());
  Vec3 twice_area = Vec3::Zero();
  const std::size_t n = face.vertices.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 a = vertices[face.vertices[i]] - mean;
    const Vec3 b = vertices[face.vertices[(i + 1) % n]] - mean;
    twice_area += a.cross(b);
  }
  face.area = 0.5 * twice_area.norm();
  face.normal = twice_area.normalized();
  Vec3 moment = Vec3::Zero();
  double weight = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 a = vertices[face.vertices[i]] - mean;
    const Vec3 b = vertices[face.vertices[(i + 1) % n]] - mean;
    const double w = a.cross(b).dot(face.normal);
    moment += w * (a + b) / 3.0;
    weight += w;
  }
  face.centroid = mean + moment / weight;
  face.offset = face.normal.dot(face.centroid);
}

}  // namespace

void ConvexPolyhedron::buildTopology(const std::vector<Vec3>& points,
                                     const std::vector<std::vector<int>>& faces) {
  vertices_ = points;
  const int nv = static_cast<int>(points.size());
  faces_.assign(faces.size(), Face{});
  // Directed edges (lower, higher, face, runs lower -> higher, position in face).
  std::vector<std::tuple<int, int, int, bool, int>> directed;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    Face& face = faces_[f];
    face.vertices = faces[f];
    fillFaceGeometry(face, vertices_);
    const std::size_t n = face.vertices.size();
    face.edges.assign(n, -1);
    for (std::size_t i = 0; i < n; ++i) {
      const int a = face.vertices[i], b = face.vertices[(i + 1) % n];
      directed.emplace_back(std::min(a, b), std::max(a, b), static_cast<int>(f), a < b,
                            static_cast<int>(i));
    }
  }
  std::sort(directed.begin(), directed.end());
  const auto inconsistent = [&](const std::string& what) {
    throw GeometryError("inconsistent polyhedron topology (" + what + "); " + std::to_string(nv) +
                        " vertices, " + std::to_string(faces.size()) + " faces");
  };
  edges_.clear();
  for (std::size_t k = 0; k < directed.size(); k += 2) {
    const auto& [a0, b0, f0, up0, i0] = directed[k];
    if (k + 1 >= directed.size()) inconsistent("open edge");
    const auto& [a1, b1, f1, up1, i1] = directed[k + 1];
    if (a0 != a1 || b0 != b1 || up0 == up1 ||
        (k + 2 < directed.size() && std::get<0>(directed[k + 2]) == a0 &&
         std::get<1>(directed[k + 2]) == b0)) {
      inconsistent("edge " + std::to_string(a0) + "-" + std::to_string(b0) +
                   " not shared by exactly two oppositely oriented faces");
    }
    const int e = static_cast<int>(edges_.size());
    // f0: the face in which the edge runs v0 -> v1 (counter-clockwise).
    edges_.push_back(up0 ? Edge{a0, b0, f0, f1} : Edge{a0, b0, f1, f0});
    faces_[f0].edges[i0] = e;
    faces_[f1].edges[i1] = e;
  }
  buildVertexAdjacency();
  buildAxes();
  const int euler = nv - static_cast<int>(edges_.size()) + static_cast<int>(faces_.size());
  if (euler != 2) inconsistent("Euler characteristic " + std::to_string(euler) + " != 2");
}

void ConvexPolyhedron::buildAxes() {
  // The first of every family of directions parallel up to sign: |d x e| <= sin(angle).
  std::vector<Vec3> directions;
  for (const Face& face : faces_) directions.push_back(face.normal);
  axis_faces_ = distinctDirections(directions, kParallelAxes);
  directions.clear();
  for (const Edge& edge : edges_) {
    directions.push_back((vertices_[edge.v1] - vertices_[edge.v0]).normalized());
  }
  axis_edges_ = distinctDirections(directions, kParallelAxes);
  box_ = findBoxFrame(*this);
}

void ConvexPolyhedron::buildVertexAdjacency() {
  const int nv = static_cast<int>(vertices_.size());
  // For every vertex, each face through it gives (next, face, previous) seen along the face.
  struct Corner {
    int next, face, prev, edge_to_next;
  };
  std::vector<std::vector<Corner>> around(nv);
  for (std::size_t f = 0; f < faces_.size(); ++f) {
    const Face& face = faces_[f];
    const std::size_t n = face.vertices.size();
    for (std::size_t i = 0; i < n; ++i) {
      around[face.vertices[i]].push_back({face.vertices[(i + 1) % n], static_cast<int>(f),
                                          face.vertices[(i + n - 1) % n], face.edges[i]});
    }
  }
  std::size_t corner_count = 0;
  for (const auto& corners : around) corner_count += corners.size();
  adjacency_ = {};
  adjacency_.begin.reserve(static_cast<std::size_t>(nv) + 1);
  adjacency_.edges.reserve(corner_count);
  adjacency_.faces.reserve(corner_count);
  adjacency_.neighbours.reserve(corner_count);
  adjacency_.begin.push_back(0);
  for (int v = 0; v < nv; ++v) {
    auto& corners = around[v];
    if (corners.size() < 3) {
      throw GeometryError("inconsistent polyhedron topology: vertex " + std::to_string(v) +
                          " lies on " + std::to_string(corners.size()) + " face(s)");
    }
    std::sort(corners.begin(), corners.end(),
              [](const Corner& a, const Corner& b) { return a.next < b.next; });
    // Walk next -> face -> prev == next of the following face: counter-clockwise seen from outside.
    int at = 0;
    for (std::size_t step = 0; step < corners.size(); ++step) {
      const Corner& c = corners[at];
      adjacency_.neighbours.push_back(c.next);
      adjacency_.edges.push_back(c.edge_to_next);
      adjacency_.faces.push_back(c.face);
      const auto it = std::lower_bound(corners.begin(), corners.end(), c.prev,
                                       [](const Corner& x, int key) { return x.next < key; });
      if (it == corners.end() || it->next != c.prev) {
        throw GeometryError("inconsistent polyhedron topology: open fan at vertex " +
                            std::to_string(v));
      }
      at = static_cast<int>(it - corners.begin());
    }
    if (at != 0) {
      throw GeometryError("inconsistent polyhedron topology: vertex " + std::to_string(v) +
                          " is not a manifold corner");
    }
    adjacency_.begin.push_back(static_cast<int>(adjacency_.neighbours.size()));
  }
}

int ConvexPolyhedron::supportIndex(const Vec3& direction, int hint) const {
  const int n = static_cast<int>(vertices_.size());
  if (n <= kBruteForceSupport) {
    int best = 0;
    double best_value = direction.dot(vertices_[0]);
    for (int i = 1; i < n; ++i) {
      const double value = direction.dot(vertices_[i]);
      if (value > best_value) {
        best = i;
        best_value = value;
      }
    }
    return best;
  }
  // Hill climbing over the vertex graph: on a convex polyhedron a vertex no neighbour improves on
  // is a global maximiser.
  int best = (hint >= 0 && hint < n) ? hint : 0;
  double best_value = direction.dot(vertices_[best]);
  bool tie = false;
  for (bool moved = true; moved;) {
    moved = false;
    tie = false;
    for (int u : vertexNeighbours()[best]) {
      const double value = direction.dot(vertices_[u]);
      if (value > best_value) {
        best = u;
        best_value = value;
        moved = true;
        break;
      }
      tie = tie || value == best_value;
    }
  }
  if (!tie) return best;
  // Several maximisers: they span an edge or a face through `best`; take the lowest index.
  int lowest = best;
  for (int f : vertexFaces()[best]) {
    for (int u : faces_[f].vertices) {
      if (u < lowest && direction.dot(vertices_[u]) == best_value) lowest = u;
    }
  }
  return lowest;
}

ConvexPolyhedron ConvexPolyhedron::transformed(const Mat3& rotation,
                                               const Vec3& translation) const {
  const double orthogonality = (rotation.transpose() * rotation - Mat3::Identity()).norm();
  if (!(orthogonality <= 1e-12) || !(rotation.determinant() > 0.0) || !translation.allFinite()) {
    throw GeometryError(
        "transformed() needs a proper rotation and a finite translation "
        "(|R^T R - I| = " +
        cat(orthogonality) + ")");
  }
  ConvexPolyhedron out = *this;
  for (Vec3& v : out.vertices_) v = rotation * v + translation;
  for (Face& face : out.faces_) {
    face.normal = rotation * face.normal;
    face.centroid = rotation * face.centroid + translation;
    face.offset = face.normal.dot(face.centroid);
  }
  out.centroid_ = rotation * centroid_ + translation;
  out.incenter_ = rotation * incenter_ + translation;
  out.inertia_ = rotation * inertia_ * rotation.transpose();
  out.box_ = findBoxFrame(out);
  return out;
}

ConvexPolyhedron ConvexPolyhedron::scaled(double factor) const {
  if (!(factor > 0.0) || !std::isfinite(factor)) {
    throw GeometryError(cat("scaled() needs a finite factor > 0, got ", factor));
  }
  ConvexPolyhedron out = *this;
  for (Vec3& v : out.vertices_) v *= factor;
  for (Face& face : out.faces_) {
    face.centroid *= factor;
    face.offset *= factor;
    face.area *= factor * factor;
  }
  const double f2 = factor * factor;
  out.volume_ *= f2 * factor;
  out.centroid_ *= factor;
  out.inertia_ *= f2 * f2 * factor;
  out.circumradius_ *= factor;
  out.inradius_ *= factor;
  out.incenter_ *= factor;
  out.box_ = findBoxFrame(out);
  return out;
}

bool ConvexPolyhedron::contains(const Vec3& x, double tolerance) const {
  return std::all_of(faces_.begin(), faces_.end(), [&](const Face& face) {
    return face.normal.dot(x) - face.offset <= tolerance;
  });
}

}  // namespace polydem::geometry

// ConvexPolyhedron: a convex polyhedron with true polygon faces (coplanar triangles merged, so a
// cube has 6 quads), unique edges, adjacency, exact mass properties and support mapping.
//
// Built from a point cloud with Qhull; every tolerance is relative to the size of the cloud, so the
// same shape in millimetres and in metres gives the same topology. The polyhedron is stored in
// whatever frame its points were given in; BodyShape (body_shape.h) moves it to its body frame.
#pragma once

#include <span>
#include <vector>

#include "polydem/core/types.h"
#include "polydem/geometry/box_frame.h"
#include "polydem/geometry/face_regions.h"
#include "polydem/geometry/jagged_view.h"

namespace polydem::geometry {

/// A plane n . x = offset, with unit normal n.
struct Plane {
  Vec3 normal = Vec3::UnitZ();
  double offset = 0.0;
  double signedDistance(const Vec3& x) const { return normal.dot(x) - offset; }
};

struct Face {
  std::vector<int> vertices;  // counter-clockwise seen from outside (right-hand rule: outward)
  std::vector<int> edges;     // edges[i] joins vertices[i] and vertices[i+1]
  Vec3 normal;                // unit, outward
  double offset = 0.0;        // normal . x = offset for x on the face
  Vec3 centroid;              // area centroid of the polygon
  double area = 0.0;
};

struct Edge {
  int v0 = -1, v1 = -1;  // v0 < v1
  int f0 = -1, f1 = -1;  // the two faces sharing the edge; the edge runs v0 -> v1 in f0's
                         // counter-clockwise order (and v1 -> v0 in f1's)
};

/// The edges, faces and neighbours of each vertex, one list per vertex stored one after another:
/// vertex v's are edges[begin[v] .. begin[v + 1]), and so on (JaggedView reads them).
struct VertexAdjacency {
  std::vector<int> begin;  // vertices + 1 entries
  std::vector<int> edges, faces, neighbours;
};

/// What fromPoints() found besides the hull: input points that are not vertices of the hull.
struct BuildReport {
  std::vector<int> interior_points;  // strictly inside the hull
  std::vector<int> boundary_points;  // on a face or an edge but not a corner
  std::vector<int> vertex_of_input;  // hull vertex i came from input point vertex_of_input[i]
};

class ConvexPolyhedron {
 public:
  ConvexPolyhedron() = default;

  /// The convex hull of `points`. Throws GeometryError for fewer than 4 points, NaN or infinite
  /// coordinates, duplicate points (closer than 1e-10 of the cloud's size) and clouds that are
  /// flat (all points within 1e-10 of the cloud's size from one plane). Points that are not hull
  /// vertices are dropped and listed in `report`. Facets coplanar within 1e-10 of the cloud's size
  /// are merged into one face. Vertices keep the order of their input points; each face starts
  /// at its lowest vertex index and the faces are sorted by their vertex lists, so the topology
  /// does not depend on qhull's internal order (nor on a rigid motion or change of unit).
  static ConvexPolyhedron fromPoints(std::span<const Vec3> points, BuildReport* report = nullptr);

  const std::vector<Vec3>& vertices() const { return vertices_; }
  const std::vector<Face>& faces() const { return faces_; }
  const std::vector<Edge>& edges() const { return edges_; }
  /// Edges, faces and neighbouring vertices of each vertex, counter-clockwise around the vertex
  /// seen from outside, starting at the lowest-index neighbour: vertexEdges()[v][k] joins v and
  /// vertexNeighbours()[v][k]; vertexFaces()[v][k] lies between edges k and k + 1.
  JaggedView vertexEdges() const { return {adjacency_.begin, adjacency_.edges}; }
  JaggedView vertexFaces() const { return {adjacency_.begin, adjacency_.faces}; }
  JaggedView vertexNeighbours() const { return {adjacency_.begin, adjacency_.neighbours}; }
  /// The arrays behind the three views above.
  const VertexAdjacency& vertexAdjacency() const { return adjacency_; }
  /// The faces whose normals differ in direction up to sign, and the edges likewise (the first of
  /// each parallel family, parallel meaning within kParallelAxes rad): the axes a separating-axis
  /// test of two polyhedra needs (contact/sat/sat.h). Indices, so they hold in any placed frame.
  const std::vector<int>& axisFaces() const { return axis_faces_; }
  const std::vector<int>& axisEdges() const { return axis_edges_; }
  static constexpr double kParallelAxes = 1e-10;
  /// The frame of a rectangular box (box_frame.h), or null if the polyhedron is not one.
  const BoxFrame* box() const { return box_ ? &*box_ : nullptr; }

  /// Exact mass properties of the solid with unit density (divergence theorem).
  double volume() const { return volume_; }
  const Vec3& centroid() const { return centroid_; }
  /// Inertia tensor about the centroid, for unit density (multiply by density for kg m^2).
  const Mat3& inertia() const { return inertia_; }

  /// Largest distance from the centroid to a vertex.
  double circumradius() const { return circumradius_; }
  /// Radius and centre of the largest inscribed sphere (Chebyshev centre of the faces).
  double inradius() const { return inradius_; }
  const Vec3& incenter() const { return incenter_; }
  /// Length scale for relative tolerances: the diameter of the circumscribed sphere.
  double lengthScale() const { return 2.0 * circumradius_; }

  /// The nearest-face partition (face_regions.h): for each face, the faces whose bisector planes
  /// bound its region. Computed on first use, kept, shared by copies (transformed() and scaled()
  /// keep it: the partition does not change).
  const FaceRegions& faceRegions() const { return face_regions_.get(*this); }

  /// Index of a vertex maximising direction . v (ties broken towards the lowest index).
  /// `hint` is a vertex to start a hill climb from on large polyhedra (more than 32 vertices; the
  /// previous answer for a nearby direction makes it a few steps). No allocation.
  int supportIndex(const Vec3& direction, int hint = 0) const;
  const Vec3& support(const Vec3& direction) const { return vertices_[supportIndex(direction)]; }

  /// The polyhedron moved by x -> rotation * x + translation (same topology and indices).
  ConvexPolyhedron transformed(const Mat3& rotation, const Vec3& translation) const;
  /// The polyhedron scaled about the origin by `factor` > 0.
  ConvexPolyhedron scaled(double factor) const;

  /// Whether x lies inside or on the boundary, within `tolerance` (absolute length).
  bool contains(const Vec3& x, double tolerance = 0.0) const;

  /// The two parts of the polyhedron on either side of `plane` (below: signedDistance <= 0).
  /// A part thinner than 1e-9 of the length scale is returned empty.
  struct Split {
    std::vector<Vec3> below, above;  // vertices of each part; empty if there is none
  };
  Split split(const Plane& plane) const;

 private:
  /// Up to this many vertices supportIndex() scans them all; above, it climbs the vertex graph.
  static constexpr int kBruteForceSupport = 32;

  void buildTopology(const std::vector<Vec3>& points, const std::vector<std::vector<int>>& faces);
  void buildVertexAdjacency();
  void buildAxes();
  void computeMassProperties();
  void computeRadii();

  std::vector<Vec3> vertices_;
  std::vector<Face> faces_;
  std::vector<Edge> edges_;
  VertexAdjacency adjacency_;
  std::vector<int> axis_faces_, axis_edges_;
  std::optional<BoxFrame> box_;
  double volume_ = 0.0;
  Vec3 centroid_ = Vec3::Zero();
  Mat3 inertia_ = Mat3::Zero();
  double circumradius_ = 0.0;
  double inradius_ = 0.0;
  Vec3 incenter_ = Vec3::Zero();
  LazyFaceRegions face_regions_;
};

}  // namespace polydem::geometry

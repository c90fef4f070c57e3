// Bindings of module/geometry: ConvexPolyhedron and the shape builders (polydem.shapes).
#include <cstdint>
#include <optional>
#include <string>

#include "bindings.h"
#include "polydem/core/strings.h"
#include "polydem/geometry/convex_polyhedron.h"
#include "polydem/geometry/shapes.h"

namespace polydem::python {

namespace {

using geometry::ConvexPolyhedron;
namespace shapes = geometry::shapes;

py::list faceList(const ConvexPolyhedron& p) {
  py::list faces;
  for (const auto& f : p.faces()) faces.append(py::cast(f.vertices));
  return faces;
}

py::array_t<double> faceNormals(const ConvexPolyhedron& p) {
  std::vector<Vec3> normals;
  normals.reserve(p.faces().size());
  for (const auto& f : p.faces()) normals.push_back(f.normal);
  return pointsArray(normals);
}

py::array_t<double> faceAreas(const ConvexPolyhedron& p) {
  auto a = emptyArray<double>({static_cast<py::ssize_t>(p.faces().size())});
  for (std::size_t i = 0; i < p.faces().size(); ++i) a.mutable_data()[i] = p.faces()[i].area;
  return a;
}

py::array_t<std::int64_t> edgeArray(const ConvexPolyhedron& p) {
  auto a = emptyArray<std::int64_t>({static_cast<py::ssize_t>(p.edges().size()), 2});
  std::int64_t* d = a.mutable_data();
  for (const auto& e : p.edges()) {
    *d++ = e.v0;
    *d++ = e.v1;
  }
  return a;
}

std::string repr(const ConvexPolyhedron& p) {
  return cat("ConvexPolyhedron(", p.vertices().size(), " vertices, ", p.faces().size(),
             " faces, volume ", num(p.volume()), ")");
}

shapes::Platonic platonicByName(const std::string& name) {
  if (name == "tetrahedron") return shapes::Platonic::kTetrahedron;
  if (name == "cube") return shapes::Platonic::kCube;
  if (name == "octahedron") return shapes::Platonic::kOctahedron;
  if (name == "dodecahedron") return shapes::Platonic::kDodecahedron;
  if (name == "icosahedron") return shapes::Platonic::kIcosahedron;
  throw py::value_error(cat("unknown Platonic solid '", name,
                            "'; known: tetrahedron, cube, octahedron, dodecahedron, icosahedron"));
}

void bindPolyhedron(py::module_& m) {
  py::class_<ConvexPolyhedron>(m, "ConvexPolyhedron",
                               R"(A convex polyhedron: the convex hull of a point cloud.

Faces are true polygons (coplanar triangles merged: a cube has 6 quads), counter-clockwise
seen from outside. Vertices keep the order of the input points that are hull corners; points
that are not corners are dropped. Mass properties are exact, for unit density.

    >>> p = polydem.ConvexPolyhedron(polydem.shapes.cube(2.0))
    >>> p.volume
    8.0

Raises polydem.GeometryError (a ValueError) for fewer than 4 points, NaN or infinite
coordinates, duplicate points and flat clouds, with polydem's message.)")
      .def(py::init([](const py::handle& points) {
             return ConvexPolyhedron::fromPoints(toPoints(points, "points"));
           }),
           py::arg("points"), "The convex hull of `points`, an (n, 3) array in metres.")
      .def_property_readonly(
          "vertices", [](const ConvexPolyhedron& p) { return pointsArray(p.vertices()); },
          "Corners, (n, 3) array [m].")
      .def_property_readonly("faces", &faceList,
                             "Faces as lists of vertex indices, counter-clockwise seen from "
                             "outside (outward normal by the right-hand rule).")
      .def_property_readonly("face_normals", &faceNormals, "Outward unit face normals, (m, 3).")
      .def_property_readonly("face_areas", &faceAreas, "Face areas, (m,) [m^2].")
      .def_property_readonly("edges", &edgeArray, "Edges as vertex index pairs, (k, 2) int64.")
      .def_property_readonly("volume", method(&ConvexPolyhedron::volume), "Volume [m^3].")
      .def_property_readonly(
          "centroid", [](const ConvexPolyhedron& p) { return vec3Array(p.centroid()); },
          "Centroid of the solid [m].")
      .def_property_readonly(
          "inertia", [](const ConvexPolyhedron& p) { return mat3Array(p.inertia()); },
          "Inertia tensor about the centroid for unit density, (3, 3) [m^5]; multiply by the\n"
          "density (kg/m^3) for kg m^2.")
      .def_property_readonly("circumradius", method(&ConvexPolyhedron::circumradius),
                             "Largest distance from the centroid to a vertex [m].")
      .def_property_readonly("inradius", method(&ConvexPolyhedron::inradius),
                             "Radius of the largest inscribed sphere [m].")
      .def_property_readonly(
          "incenter", [](const ConvexPolyhedron& p) { return vec3Array(p.incenter()); },
          "Centre of the largest inscribed sphere [m].")
      .def_property_readonly("length_scale", method(&ConvexPolyhedron::lengthScale),
                             "Twice the circumradius: the length relative tolerances scale with.")
      .def(
          "support",
          [](const ConvexPolyhedron& p, const py::handle& d) {
            return vec3Array(p.support(toVec3(d, "direction")));
          },
          py::arg("direction"),
          "The vertex farthest along `direction` (ties: the lowest index), as a 3-vector.")
      .def(
          "support_index",
          [](const ConvexPolyhedron& p, const py::handle& d) {
            return p.supportIndex(toVec3(d, "direction"));
          },
          py::arg("direction"), "Index of the vertex support(direction) returns.")
      .def(
          "contains",
          [](const ConvexPolyhedron& p, const py::handle& x, double tolerance) {
            return p.contains(toVec3(x, "point"), tolerance);
          },
          py::arg("point"), py::arg("tolerance") = 0.0,
          "Whether `point` lies inside or on the boundary, within `tolerance` [m].")
      .def(
          "transformed",
          [](const ConvexPolyhedron& p, const py::handle& rotation, const py::handle& t) {
            return p.transformed(toMat3(rotation, "rotation"), toVec3(t, "translation"));
          },
          py::arg("rotation"), py::arg("translation"),
          "The polyhedron moved by x -> rotation @ x + translation (same indices).")
      .def("scaled", method(&ConvexPolyhedron::scaled), py::arg("factor"),
           "The polyhedron scaled about the origin by `factor` > 0.")
      .def("__repr__", &repr);
}

void bindShapes(py::module_& m) {
  auto s = m.def_submodule("shapes", R"(Vertex lists of the shapes of scene files and benchmarks.

Each function returns the corners of a convex polyhedron as an (n, 3) array in metres; build the
polyhedron with polydem.ConvexPolyhedron(polydem.shapes.cube(1.0)). Invalid sizes raise
polydem.GeometryError.)");
  s.def(
      "box",
      [](const py::handle& lo, const py::handle& hi) {
        return pointsArray(shapes::box(toVec3(lo, "lo"), toVec3(hi, "hi")));
      },
      py::arg("lo"), py::arg("hi"), "Axis-aligned box with opposite corners lo < hi.");
  s.def(
      "box_around",
      [](const py::handle& centre, const py::handle& half) {
        return pointsArray(
            shapes::boxAround(toVec3(centre, "centre"), toVec3(half, "half_extents")));
      },
      py::arg("centre"), py::arg("half_extents"),
      "Axis-aligned box centred at `centre` with the given half-extents.");
  s.def(
      "prism",
      [](const py::handle& base, const py::handle& extrusion) {
        return pointsArray(shapes::prism(toPoints(base, "base"), toVec3(extrusion, "extrusion")));
      },
      py::arg("base"), py::arg("extrusion"),
      "The planar convex polygon `base` (corners in order, (k, 3)) and its copy moved by\n"
      "`extrusion`.");
  s.def(
      "ridge_prism",
      [](const py::handle& a, const py::handle& b, double half_width, double height) {
        return pointsArray(
            shapes::ridgePrism(toVec3(a, "ridge_a"), toVec3(b, "ridge_b"), half_width, height));
      },
      py::arg("ridge_a"), py::arg("ridge_b"), py::arg("base_half_width"), py::arg("height"),
      "Triangular prism with a horizontal ridge from ridge_a to ridge_b on top and its base\n"
      "rectangle `height` below, `base_half_width` to either side of the ridge line.");
  s.def(
      "square_pyramid",
      [](const py::handle& apex, double side, double height, const std::string& direction,
         double turn) {
        if (direction != "up" && direction != "down") {
          throw py::value_error("direction must be 'up' or 'down', got '" + direction + "'");
        }
        return pointsArray(shapes::squarePyramid(
            toVec3(apex, "apex"), side, height,
            direction == "up" ? shapes::Apex::kUp : shapes::Apex::kDown, turn));
      },
      py::arg("apex"), py::arg("base_side"), py::arg("height"), py::arg("direction") = "up",
      py::arg("turn") = 0.0,
      "Square pyramid with its apex at `apex`, the base `height` below ('up') or above ('down')\n"
      "it, turned by `turn` radians about the vertical axis.");
  s.def(
      "platonic",
      [](const std::string& name, std::optional<double> edge, std::optional<double> radius) {
        if (edge.has_value() == radius.has_value()) {
          throw py::value_error("platonic: give exactly one of edge and circumradius");
        }
        const auto solid = platonicByName(name);
        return pointsArray(edge ? shapes::platonic(solid, *edge)
                                : shapes::platonicWithCircumradius(solid, *radius));
      },
      py::arg("name"), py::arg("edge") = py::none(), py::arg("circumradius") = py::none(),
      "A Platonic solid centred at the origin ('tetrahedron', 'cube', 'octahedron',\n"
      "'dodecahedron', 'icosahedron') of the given edge length or circumradius.");
  for (const char* name : {"tetrahedron", "cube", "octahedron", "dodecahedron", "icosahedron"}) {
    const auto solid = platonicByName(name);
    s.def(
        name, [solid](double edge) { return pointsArray(shapes::platonic(solid, edge)); },
        py::arg("edge"),
        cat("The regular ", name, " of the given edge length, centred at the origin (see\n",
            "geometry/shapes.h for its orientation).")
            .c_str());
  }
  s.def(
      "hexagonal_prism",
      [](double side, double length) { return pointsArray(shapes::hexagonalPrism(side, length)); },
      py::arg("side"), py::arg("length"),
      "Hexagonal rod centred at the origin, axis along z, hexagon of side `side`.");
  s.def(
      "random_convex",
      [](int n, std::uint64_t seed, const py::handle& semi_axes, double perturbation) {
        return pointsArray(
            shapes::randomConvex(n, seed, toVec3(semi_axes, "semi_axes"), perturbation));
      },
      py::arg("n"), py::arg("seed"), py::arg("semi_axes") = py::make_tuple(1.0, 1.0, 1.0),
      py::arg("perturbation") = 0.0,
      "`n` points (4 to 100000) on an ellipsoid with the given semi-axes (each scaled by a\n"
      "factor in [1 - perturbation, 1 + perturbation]), from the seed: the same bits on every\n"
      "machine. polydem.GeometryError (a ValueError) for another n.");
}

}  // namespace

void bindGeometry(py::module_& m) {
  bindPolyhedron(m);
  bindShapes(m);
}

}  // namespace polydem::python

"""Vertex lists of the shapes of scene files and benchmarks (module/geometry/shapes.h).

Each function returns the corners of a convex polyhedron as an (n, 3) numpy array in metres;
build the polyhedron with polydem.ConvexPolyhedron(polydem.shapes.cube(1.0)). Invalid sizes raise
polydem.GeometryError.
"""
from ._polydem.shapes import (
    box,
    box_around,
    cube,
    dodecahedron,
    hexagonal_prism,
    icosahedron,
    octahedron,
    platonic,
    prism,
    random_convex,
    ridge_prism,
    square_pyramid,
    tetrahedron,
)

__all__ = [
    "box", "box_around", "cube", "dodecahedron", "hexagonal_prism", "icosahedron", "octahedron",
    "platonic", "prism", "random_convex", "ridge_prism", "square_pyramid", "tetrahedron",
]

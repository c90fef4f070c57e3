"""polydem.ConvexPolyhedron and polydem.shapes against analytical mass properties and topology.

Run by ctest (python_geometry) with PYTHONPATH=build/python and /usr/bin/python3.
"""
import math
import unittest

import numpy as np

import polydem


class CubeMassProperties(unittest.TestCase):
    """A cube of edge a: V = a^3, I = a^5 / 6 (unit density) on the diagonal, R = a sqrt(3) / 2,
    r = a / 2, at any scale (the geometry is scale-free)."""

    def check_cube(self, a, centre):
        p = polydem.ConvexPolyhedron(polydem.shapes.box_around(centre, [a / 2] * 3))
        self.assertEqual(p.vertices.shape, (8, 3))
        self.assertEqual(len(p.faces), 6)
        self.assertTrue(all(len(f) == 4 for f in p.faces))
        self.assertEqual(p.edges.shape, (12, 2))
        rel = 1e-13
        self.assertAlmostEqual(p.volume / a**3, 1.0, delta=rel)
        np.testing.assert_allclose(p.centroid, centre, rtol=0, atol=rel * a)
        np.testing.assert_allclose(p.inertia, np.eye(3) * a**5 / 6, rtol=0, atol=rel * a**5)
        self.assertAlmostEqual(p.circumradius / (a * math.sqrt(3) / 2), 1.0, delta=rel)
        self.assertAlmostEqual(p.inradius / (a / 2), 1.0, delta=1e-9)
        np.testing.assert_allclose(p.incenter, centre, rtol=0, atol=1e-9 * a)
        np.testing.assert_allclose(p.face_areas, np.full(6, a * a), rtol=rel)
        # Outward unit normals: each points from the centroid to its face.
        for f, n in zip(p.faces, p.face_normals):
            self.assertAlmostEqual(np.linalg.norm(n), 1.0, delta=1e-15)
            self.assertGreater(np.dot(p.vertices[f].mean(axis=0) - centre, n), 0.49 * a)

    def test_unit_cube(self):
        self.check_cube(1.0, np.zeros(3))

    def test_scales(self):
        for a in (1e-3, 1e3):
            with self.subTest(a=a):
                self.check_cube(a, np.array([3.0, -2.0, 0.5]) * a)

    def test_cube_builder_matches_box(self):
        p = polydem.ConvexPolyhedron(polydem.shapes.cube(2.0))
        q = polydem.ConvexPolyhedron(polydem.shapes.box([-1, -1, -1], [1, 1, 1]))
        self.assertAlmostEqual(p.volume, q.volume, delta=1e-14 * q.volume)
        np.testing.assert_allclose(p.inertia, q.inertia, rtol=0, atol=1e-14 * q.inertia[0, 0])


class Support(unittest.TestCase):
    def test_support_of_cube(self):
        p = polydem.ConvexPolyhedron(polydem.shapes.cube(2.0))
        np.testing.assert_array_equal(p.support([1, 2, 3]), [1, 1, 1])
        np.testing.assert_array_equal(p.support(np.array([-1.0, 0.5, -3.0])), [-1, 1, -1])
        self.assertEqual(p.vertices[p.support_index([1, -1, 1])].tolist(), [1, -1, 1])

    def test_contains(self):
        p = polydem.ConvexPolyhedron(polydem.shapes.cube(2.0))
        self.assertTrue(p.contains([0.5, -0.5, 0.99]))
        self.assertFalse(p.contains([0.5, -0.5, 1.01]))
        self.assertTrue(p.contains([0.5, -0.5, 1.01], tolerance=0.02))

    def test_transformed_and_scaled(self):
        p = polydem.ConvexPolyhedron(polydem.shapes.tetrahedron(1.0))
        c, s = math.cos(0.3), math.sin(0.3)
        r = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
        q = p.transformed(r, [1, 2, 3])
        self.assertAlmostEqual(q.volume, p.volume, delta=1e-14)
        np.testing.assert_allclose(q.centroid, r @ p.centroid + [1, 2, 3], atol=1e-14)
        self.assertAlmostEqual(p.scaled(2.0).volume, 8 * p.volume, delta=1e-14)


class Shapes(unittest.TestCase):
    def test_platonic_solids(self):
        # Volume per edge^3 of the five solids.
        expected = {
            "tetrahedron": (4, 4, 1 / (6 * math.sqrt(2))),
            "cube": (8, 6, 1.0),
            "octahedron": (6, 8, math.sqrt(2) / 3),
            "dodecahedron": (20, 12, (15 + 7 * math.sqrt(5)) / 4),
            "icosahedron": (12, 20, 5 * (3 + math.sqrt(5)) / 12),
        }
        for name, (n_vertices, n_faces, volume) in expected.items():
            with self.subTest(name):
                p = polydem.ConvexPolyhedron(getattr(polydem.shapes, name)(0.5))
                self.assertEqual(len(p.vertices), n_vertices)
                self.assertEqual(len(p.faces), n_faces)
                self.assertAlmostEqual(p.volume / (volume * 0.125), 1.0, delta=1e-12)
                q = polydem.ConvexPolyhedron(polydem.shapes.platonic(name, circumradius=2.0))
                self.assertAlmostEqual(q.circumradius, 2.0, delta=1e-12)

    def test_other_builders(self):
        prism = polydem.ConvexPolyhedron(
            polydem.shapes.prism([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [0, 0, 2]))
        self.assertAlmostEqual(prism.volume, 1.0, delta=1e-14)
        rod = polydem.ConvexPolyhedron(polydem.shapes.hexagonal_prism(1.0, 2.0))
        self.assertAlmostEqual(rod.volume, 3 * math.sqrt(3) / 2 * 2.0, delta=1e-13)
        ridge = polydem.ConvexPolyhedron(
            polydem.shapes.ridge_prism([-1, 0, 0], [1, 0, 0], 0.5, 1.0))
        self.assertAlmostEqual(ridge.volume, 0.5 * 1.0 * 1.0 * 2.0, delta=1e-14)
        pyramid = polydem.ConvexPolyhedron(
            polydem.shapes.square_pyramid([0, 0, 0], 1.0, 3.0, direction="down"))
        self.assertAlmostEqual(pyramid.volume, 1.0, delta=1e-14)
        self.assertAlmostEqual(pyramid.vertices[:, 2].max(), 3.0, delta=1e-15)
        a = polydem.shapes.random_convex(30, 7, [1, 2, 3], 0.1)
        self.assertEqual(a.shape, (30, 3))
        np.testing.assert_array_equal(a, polydem.shapes.random_convex(30, 7, [1, 2, 3], 0.1))
        with self.assertRaisesRegex(polydem.GeometryError, "4 <= n <= 100000 points, got 2000000000"):
            polydem.shapes.random_convex(2000000000, 7)  # refused before 48 GB are asked for


class Errors(unittest.TestCase):
    def test_too_few_points(self):
        with self.assertRaises(polydem.GeometryError) as e:
            polydem.ConvexPolyhedron([[0, 0, 0], [1, 0, 0], [0, 1, 0]])
        self.assertIsInstance(e.exception, ValueError)
        self.assertIn("3", str(e.exception))

    def test_flat_and_nan_and_duplicate(self):
        flat = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
        nan = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, float("nan")]]
        duplicate = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [0, 0, 1]]
        for points in (flat, nan, duplicate):
            with self.subTest(points=points), self.assertRaises(ValueError) as e:
                polydem.ConvexPolyhedron(points)
            self.assertIsInstance(e.exception, polydem.Error)
            self.assertTrue(str(e.exception))

    def test_bad_arrays(self):
        for bad in ([[0, 0], [1, 1]], np.zeros(12), "cube", [[0, 0, "x"]]):
            with self.subTest(bad=bad), self.assertRaises(ValueError) as e:
                polydem.ConvexPolyhedron(bad)
            self.assertIn("points", str(e.exception))
        with self.assertRaises(ValueError):
            polydem.ConvexPolyhedron(polydem.shapes.cube(1.0)).support([1, 0])

    def test_bad_sizes(self):
        with self.assertRaises(polydem.GeometryError):
            polydem.shapes.box([0, 0, 0], [1, -1, 1])
        with self.assertRaises(polydem.GeometryError):
            polydem.shapes.cube(-1.0)
        with self.assertRaises(ValueError):
            polydem.shapes.platonic("cube")
        with self.assertRaises(ValueError):
            polydem.shapes.platonic("sphere", edge=1.0)


if __name__ == "__main__":
    unittest.main()

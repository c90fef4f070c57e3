"""polydem.collide, polydem.kernels and polydem.contact_cases against the analytical answers of
BENCHMARKS.md section C (Keissar tables 3.1-3.6).

Run by ctest (python_contact) with PYTHONPATH=build/python and /usr/bin/python3.
"""
import math
import unittest

import numpy as np

import polydem

# Correctness criteria of BENCHMARKS.md section C (contact/contact_cases.h).
NORMAL_RAD = 1e-6
POINT_REL = 1e-6
DEPTH_REL = 1e-3


def angle_between(u, v):
    """Angle between two unit vectors, accurate for tiny angles."""
    return 2.0 * math.atan2(np.linalg.norm(u - v), np.linalg.norm(u + v))


def case(case_id):
    cases = {c["id"]: c for c in polydem.contact_cases()}
    return cases[case_id]


class Kernels(unittest.TestCase):
    def test_names(self):
        names = polydem.kernels()
        self.assertIn("gjk-epa-ipm", names)
        self.assertIn("gjk-epa", names)
        self.assertEqual(len(names), len(set(names)))

    def test_cases(self):
        cases = polydem.contact_cases()
        self.assertEqual([c["id"] for c in cases],
                         ["C-VV", "C-VE", "C-VF", "C-EEp", "C-EEx", "C-EF", "C-FF"])
        for c in cases:
            self.assertEqual(c["a"].shape[1], 3)
            self.assertEqual(c["b"].shape[1], 3)
            np.testing.assert_array_equal(c["normal"], [0, 0, 1])
            self.assertEqual(c["depth"], 1e-5)


class FaceFace(unittest.TestCase):
    """C-FF: a unit cube on a large block, off its centre. IPM places the point in the middle of
    the overlap polygon: normal (0,0,1), point (0,0,-5e-6), depth 1e-5."""

    def check(self, result, c, scale=1.0, shift=np.zeros(3)):
        self.assertTrue(result["contact"])
        self.assertNotIn("status", result)
        self.assertLess(angle_between(result["normal"], c["normal"]), NORMAL_RAD)
        point_error = np.linalg.norm(result["point"] - (scale * c["point"] + shift))
        self.assertLess(point_error / (scale * c["size"]), POINT_REL)
        self.assertLess(abs(result["depth"] - scale * c["depth"]) / (scale * c["depth"]), DEPTH_REL)

    def test_gjk_epa_ipm(self):
        c = case("C-FF")
        self.check(polydem.collide(c["a"], c["b"], kernel="gjk-epa-ipm"), c)

    def test_default_kernel_and_polyhedron_arguments(self):
        c = case("C-FF")
        a, b = polydem.ConvexPolyhedron(c["a"]), polydem.ConvexPolyhedron(c["b"])
        self.check(polydem.collide(a, b), c)

    def test_scale_free(self):
        c = case("C-FF")
        shift = np.array([10.0, -3.0, 2.0])
        for scale in (1e-3, 1e3):
            with self.subTest(scale=scale):
                r = polydem.collide(scale * c["a"] + shift * scale, scale * c["b"] + shift * scale,
                                    kernel="gjk-epa-ipm")
                self.check(r, c, scale, shift * scale)

    def test_swapped_bodies_reverse_the_normal(self):
        c = case("C-FF")
        r = polydem.collide(c["b"], c["a"], kernel="gjk-epa-ipm")
        self.assertLess(angle_between(r["normal"], -c["normal"]), NORMAL_RAD)


class Separated(unittest.TestCase):
    def test_every_kernel_sees_no_contact(self):
        a = polydem.shapes.box([0, 0, 1.1], [1, 1, 2.1])
        b = polydem.shapes.box([0, 0, 0], [1, 1, 1])
        for name in polydem.kernels():
            with self.subTest(kernel=name):
                self.assertEqual(polydem.collide(a, b, kernel=name), {"contact": False})


class Errors(unittest.TestCase):
    def test_unknown_kernel(self):
        c = case("C-FF")
        with self.assertRaises(ValueError) as e:
            polydem.collide(c["a"], c["b"], kernel="gjk-epa-imp")
        message = str(e.exception)
        self.assertIn("gjk-epa-imp", message)
        for name in polydem.kernels():
            self.assertIn(name, message)

    def test_bad_points(self):
        c = case("C-FF")
        with self.assertRaises(polydem.GeometryError):
            polydem.collide(c["a"][:3], c["b"])
        with self.assertRaises(ValueError) as e:
            polydem.collide(c["a"], c["b"][:, :2])
        self.assertIn("b", str(e.exception))


if __name__ == "__main__":
    unittest.main()

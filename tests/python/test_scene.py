"""polydem.read_scene / parse_scene: the fields of a scene, overrides, and errors with file and line.

Run by ctest (python_scene) with PYTHONPATH=build/python and /usr/bin/python3.
"""
import copy
import os
import tempfile
import unittest

import numpy as np

import polydem

SOURCE = os.environ.get("POLYDEM_SOURCE_DIR",
                        os.path.join(os.path.dirname(__file__), os.pardir, os.pardir))
SCENE = os.path.join(SOURCE, "benchmark_scenes", "S-BLOCK-ON-PLANE.toml")

MINIMAL = """\
[scene]
id = "T-PY"

[simulation]
dt = "1 ms"
end_time = 0.5

[[material]]
name = "rock"
density = "2.5 g/cm^3"
kn = 1e8
"""


class ReadScene(unittest.TestCase):
    def test_fields(self):
        s = polydem.read_scene(SCENE)
        self.assertEqual(s.id, "S-BLOCK-ON-PLANE")
        self.assertEqual(s.file, SCENE)
        self.assertEqual(s.kernel, "gjk-epa-ipm")
        self.assertEqual(s.dt, 1e-4)
        self.assertEqual(s.end_time, 10.0)
        self.assertIsNone(s.steps)
        np.testing.assert_array_equal(s.gravity, [0, 0, -9.81])
        self.assertEqual(s.num_particles, 2)
        self.assertEqual(s.monitor, ["cube"])
        self.assertFalse(s.equilibrium)
        self.assertEqual(len(s.materials), 1)
        rock = s.materials[0]
        self.assertEqual((rock["name"], rock["density"], rock["kn"], rock["ks"]),
                         ("rock", 2650.0, 1e9, 0.5e9))
        self.assertEqual([sh["name"] for sh in s.shapes], ["cube", "base"])
        self.assertEqual(s.shapes[0]["vertices"].shape, (8, 3))
        self.assertEqual([c["name"] for c in s.checks],
                         ["centroid drift", "rotation about z", "rotation"])

    def test_particles(self):
        p = polydem.read_scene(SCENE).particles
        np.testing.assert_array_equal(p["uid"], [1, 2])  # file order, from 1
        self.assertEqual(p["label"], ["base", "cube"])
        np.testing.assert_array_equal(p["fixed"], [True, False])
        np.testing.assert_array_equal(p["shape"], [1, 0])
        np.testing.assert_array_equal(p["position"][1], [0, 0, 0.49997400265])
        np.testing.assert_array_equal(p["orientation"], [[1, 0, 0, 0]] * 2)
        self.assertEqual(p["velocity"].shape, (2, 3))

    def test_path_like(self):
        import pathlib
        self.assertEqual(polydem.read_scene(pathlib.Path(SCENE)).id, "S-BLOCK-ON-PLANE")


class Overrides(unittest.TestCase):
    def test_contact_model(self):
        s = polydem.read_scene(SCENE)
        self.assertEqual(s.contact_model, "sub-contacts")
        s.contact_model = "point"
        self.assertEqual(s.contact_model, "point")
        with self.assertRaises(ValueError) as e:
            s.contact_model = "3dec"
        self.assertIn("sub-contacts, point", str(e.exception))
        self.assertEqual(s.contact_model, "point")
        self.assertEqual(s.materials[0]["jkn"], 0.0)

    def test_kernel(self):
        s = polydem.read_scene(SCENE)
        s.kernel = "gjk-epa"
        self.assertEqual(s.kernel, "gjk-epa")
        with self.assertRaises(ValueError) as e:
            s.kernel = "no-such-kernel"
        self.assertIn("no-such-kernel", str(e.exception))
        self.assertEqual(s.kernel, "gjk-epa")

    def test_stop_condition_is_replaced(self):
        s = polydem.read_scene(SCENE)
        s.steps = 100
        self.assertEqual((s.steps, s.end_time), (100, None))
        s.end_time = 0.25
        self.assertEqual((s.steps, s.end_time), (None, 0.25))
        for bad in (0, -5):
            with self.assertRaises(ValueError):
                s.steps = bad
        with self.assertRaises(ValueError):
            s.end_time = 0.0
        self.assertEqual((s.steps, s.end_time), (None, 0.25))

    def test_copies_are_independent(self):
        s = polydem.read_scene(SCENE)
        for t in (s.copy(), copy.copy(s), copy.deepcopy(s)):
            t.kernel = "gjk-epa"
            t.steps = 3
            self.assertEqual((s.kernel, s.end_time, s.steps), ("gjk-epa-ipm", 10.0, None))


class Errors(unittest.TestCase):
    def test_parse_error_names_the_line(self):
        text = MINIMAL + 'ks = "30 deg"\n'  # line 12: an angle for a stiffness
        with self.assertRaises(polydem.InputError) as e:
            polydem.parse_scene(text, "bad.toml")
        self.assertIsInstance(e.exception, ValueError)
        self.assertTrue(str(e.exception).startswith("bad.toml:12: "), str(e.exception))
        self.assertIn("ks", str(e.exception))
        self.assertEqual((e.exception.file, e.exception.line), ("bad.toml", 12))

    def test_bad_scene_file(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "typo.toml")
            with open(path, "w") as f:
                f.write(MINIMAL.replace("end_time = 0.5", "end_tme = 0.5"))
            with self.assertRaises(polydem.InputError) as e:
                polydem.read_scene(path)
            self.assertTrue(str(e.exception).startswith(path + ":6: "), str(e.exception))
            self.assertIn("end_tme", str(e.exception))
            self.assertEqual(e.exception.line, 6)

    def test_missing_file(self):
        with self.assertRaises(polydem.InputError) as e:
            polydem.read_scene("/nonexistent/scene.toml")
        self.assertIn("/nonexistent/scene.toml", str(e.exception))


if __name__ == "__main__":
    unittest.main()

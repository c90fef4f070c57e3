"""Every scene file of benchmark_scenes/ read into a polydem.Scene (Scene.load), written back as
TOML (to_toml) and read again gives the scene the file gives: the same particles, materials,
shapes, drivers, checks, rock masses (cut again: same blocks) and settings, bit for bit; and a
loaded scene can be changed and extended in Python.
"""
import glob
import os
import unittest

import numpy as np

import polydem

polydem.set_log_level("warning")
SOURCE = os.environ["POLYDEM_SOURCE_DIR"]
SCENES = sorted(glob.glob(os.path.join(SOURCE, "benchmark_scenes", "**", "*.toml"),
                          recursive=True))
SETTINGS = ("id", "title", "description", "source", "kernel", "contact_model", "broadphase",
            "dt", "end_time", "steps", "contact_margin", "monitor", "equilibrium",
            "num_particles")


def without_lines(entries):
    """Dicts of a scene's lists without their 'line' (where the entry stood in its file)."""
    return [{k: x for k, x in e.items() if k != "line"} for e in entries]


def same(a, b):
    """Equal values, numpy arrays (bit for bit) and dicts or lists of them included."""
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    if isinstance(a, np.ndarray):
        return a.dtype == b.dtype and np.array_equal(a, b)
    return a == b


class RoundTrip(unittest.TestCase):
    def test_every_benchmark_scene(self):
        self.assertGreater(len(SCENES), 10)
        for path in SCENES:
            with self.subTest(scene=os.path.relpath(path, SOURCE)):
                original = polydem.read_scene(path)
                loaded = polydem.Scene.load(path)
                again = polydem.parse_scene(loaded.to_toml(), "round trip")
                for key in SETTINGS:
                    self.assertTrue(same(getattr(original, key), getattr(again, key)), key)
                self.assertTrue(same(original.gravity, again.gravity))
                self.assertTrue(same(original.particles, again.particles))
                self.assertTrue(same(original.materials, again.materials))
                self.assertTrue(same(original.shapes, again.shapes))
                self.assertTrue(same(original.drivers, again.drivers))
                self.assertTrue(same(without_lines(original.checks), without_lines(again.checks)))
                self.assertTrue(same(without_lines(original.rock_masses),
                                     without_lines(again.rock_masses)))
                # The uids the loaded Scene counted are those the reader gave.
                self.assertEqual(loaded._next_uid, original.num_particles + 1)

    def test_same_run(self):
        path = os.path.join(SOURCE, "benchmark_scenes", "S-25-CUBES.toml")
        a = polydem.Simulation(path)
        a.step(20)
        b = polydem.Simulation(polydem.Scene.load(path))
        b.step(20)
        self.assertEqual(a.state_hash(), b.state_hash())


class ChangeALoadedScene(unittest.TestCase):
    def test_extend_and_change(self):
        path = os.path.join(SOURCE, "benchmark_scenes", "S-BLOCK-ON-PLANE.toml")
        s = polydem.Scene.load(path)
        uid = s.add_particle("cube", "rock", position=(0.5, 0.5, 3), label="dropped")
        self.assertEqual(uid, 3)
        s.set_particle(2, velocity=(0.1, 0, 0))  # the file's "cube"
        s.end_time = 0.01
        built = s.build()
        self.assertEqual(built.particles["label"], ["base", "cube", "dropped"])
        self.assertEqual(built.particles["velocity"][1].tolist(), [0.1, 0, 0])
        self.assertEqual(built.particles["position"][1].tolist(), [0, 0, 0.49997400265])
        self.assertEqual(built.end_time, 0.01)
        self.assertEqual(built.kernel, polydem.read_scene(path).kernel)

    def test_not_toml(self):
        with self.assertRaisesRegex(ValueError, "not TOML"):
            polydem.Scene.from_toml("[scene\nid = 1", "broken.toml")


if __name__ == "__main__":
    unittest.main()

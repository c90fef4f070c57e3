"""polydem.run and polydem.Simulation on one rank: the same state hash as `polydem run` with the
same settings, and the particle state as numpy arrays.

Run by ctest (python_run) after the fixture python_reference_run, which runs
`polydem run $POLYDEM_REFERENCE_SCENE --end-time $POLYDEM_REFERENCE_END_TIME --out
$POLYDEM_REFERENCE_RUN`; the test compares with the state_hash of its summary.json.
"""
import json
import os
import shutil
import unittest

import numpy as np

import polydem

SCENE = os.environ["POLYDEM_REFERENCE_SCENE"]  # S-BLOCK-ON-PLANE: a cube resting on a block
END_TIME = float(os.environ["POLYDEM_REFERENCE_END_TIME"])
WORK = os.environ.get("POLYDEM_TEST_WORK", "/tmp/polydem_python_test")


def reference_hash():
    with open(os.path.join(os.environ["POLYDEM_REFERENCE_RUN"], "summary.json")) as f:
        return json.load(f)["state_hash"]


def reference_scene():
    scene = polydem.read_scene(SCENE)
    scene.end_time = END_TIME
    return scene


class Run(unittest.TestCase):
    def test_hash_matches_the_command_line(self):
        r = polydem.run(SCENE, end_time=END_TIME)
        self.assertEqual(r["state_hash"], reference_hash())
        self.assertEqual(r["steps"], round(END_TIME / 1e-4))
        self.assertAlmostEqual(r["time"], END_TIME, delta=1e-15)
        self.assertEqual(r["equilibrium_steps"], 0)
        self.assertGreater(r["wall_seconds"], 0.0)
        # The cube stays put under IPM: every check of the scene holds.
        self.assertEqual([c["name"] for c in r["checks"]],
                         ["centroid drift", "rotation about z", "rotation"])
        for c in r["checks"]:
            self.assertTrue(c["pass"], c)
        self.assertTrue(r["all_checks_pass"])

    def test_scene_object_and_output_directory(self):
        out = os.path.join(WORK, "run_out")
        shutil.rmtree(out, ignore_errors=True)
        r = polydem.run(reference_scene(), out=out, snapshots=False)
        self.assertEqual(r["state_hash"], reference_hash())
        with open(os.path.join(out, "summary.json")) as f:
            self.assertEqual(json.load(f)["state_hash"], r["state_hash"])
        header, series = polydem.plots.read_series(os.path.join(out, "series.csv"))
        self.assertIn("cube_z", header)
        self.assertEqual(series["time"][-1], r["time"])
        np.testing.assert_allclose(series["cube_z"], 0.49997400265, rtol=0, atol=1e-6)
        png = polydem.plots.plot(out, columns=["cube_z"])
        with open(png, "rb") as f:
            self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")

    def test_overrides_and_errors(self):
        r = polydem.run(SCENE, steps=7, kernel="gjk-epa")
        self.assertEqual(r["steps"], 7)
        with self.assertRaises(ValueError):
            polydem.run(SCENE, steps=10, kernel="nope")
        with self.assertRaises(ValueError):
            polydem.run(SCENE, end_time=-1.0)
        with self.assertRaises(polydem.InputError):
            polydem.run(os.path.join(WORK, "missing.toml"))


class Stepping(unittest.TestCase):
    def test_steps_give_the_same_hash(self):
        sim = polydem.Simulation(reference_scene())
        self.assertEqual((sim.step_count, sim.time, sim.stage), (0, 0.0, "main"))
        sim.step(0)
        self.assertEqual(sim.step_count, 0)
        n = round(END_TIME / sim.dt)
        sim.step(n - 10)
        sim.step(10)
        self.assertEqual(sim.step_count, n)
        self.assertAlmostEqual(sim.time, END_TIME, delta=1e-15)
        self.assertEqual(sim.state_hash(), reference_hash())
        with self.assertRaises(ValueError):
            sim.step(-1)

    def test_particle_arrays(self):
        scene = reference_scene()
        sim = polydem.Simulation(scene)
        sim.step(100)
        p = sim.particles()
        self.assertEqual(set(p), {"uid", "position", "orientation", "velocity",
                                  "angular_velocity", "shape", "material", "flags", "label"})
        self.assertEqual(p["label"], scene.particles["label"])  # by uid: ["base", "cube"]
        n = scene.num_particles
        for key, shape, kind in (("uid", (n,), "u"), ("position", (n, 3), "f"),
                                 ("orientation", (n, 4), "f"), ("velocity", (n, 3), "f"),
                                 ("angular_velocity", (n, 3), "f"), ("shape", (n,), "i"),
                                 ("material", (n,), "i"), ("flags", (n,), "u")):
            self.assertEqual(p[key].shape, shape, key)
            self.assertEqual(p[key].dtype.kind, kind, key)
        np.testing.assert_array_equal(p["uid"], [1, 2])
        np.testing.assert_array_equal(p["flags"], [polydem.FLAG_FIXED, 0])
        np.testing.assert_array_equal(p["shape"], scene.particles["shape"])
        # The base: box min (-1.2, -1.5, -1) max (2.8, 2.5, 0), centroid (0.8, 0.5, -0.5), still.
        np.testing.assert_allclose(p["position"][0], [0.8, 0.5, -0.5], rtol=0, atol=1e-15)
        np.testing.assert_array_equal(p["velocity"][0], [0, 0, 0])
        np.testing.assert_array_equal(p["angular_velocity"][0], [0, 0, 0])
        # The cube rests where it started (static penetration m g / kn), turned by nothing.
        np.testing.assert_allclose(p["position"][1], scene.particles["position"][1], rtol=0,
                                   atol=1e-6)
        np.testing.assert_allclose(np.linalg.norm(p["orientation"], axis=1), 1.0, atol=1e-15)
        np.testing.assert_allclose(p["orientation"][1], [1, 0, 0, 0], atol=1e-6)
        self.assertLess(np.abs(p["velocity"][1]).max(), 1e-3)
        # Gathering on one rank gives the same arrays.
        g = sim.particles(gather=True)
        for key in p:
            np.testing.assert_array_equal(g[key], p[key], key)
        # The body-frame shape table: the unit cube centred at the origin.
        cube = sim.shapes[p["shape"][1]]
        self.assertAlmostEqual(cube.volume, 1.0, delta=1e-14)
        np.testing.assert_allclose(cube.centroid, 0.0, atol=1e-15)

    def test_contacts_and_monitors(self):
        scene = reference_scene()
        sim = polydem.Simulation(scene)
        sim.step(10)
        m = sim.monitors()
        self.assertEqual((m["particles"], m["contacts"], m["step"]), (1, 1, 10))
        self.assertGreaterEqual(m["kinetic_energy"], 0.0)
        c = sim.contacts()
        np.testing.assert_array_equal(c["uids"], [[1, 2]])
        # From the cube (higher uid) into the base: straight down; the force on the base is the
        # cube's weight, m g = 2650 kg * 9.81 m/s^2, borne by a spring kn at depth m g / kn.
        np.testing.assert_allclose(c["normal"][0], [0, 0, -1], atol=1e-12)
        weight = scene.materials[0]["density"] * 1.0 * 9.81
        self.assertLess(abs(c["force"][0][2] + weight) / weight, 1e-3)
        self.assertLess(abs(c["normal_force"][0] - weight) / weight, 1e-3)

    def test_run_and_path(self):
        scene = polydem.read_scene(SCENE)
        scene.steps = 25
        sim = polydem.Simulation(scene)
        self.assertEqual(sim.run(), "step limit")
        self.assertEqual(sim.step_count, 25)
        self.assertEqual(polydem.Simulation(SCENE).scene.id, "S-BLOCK-ON-PLANE")
        self.assertIn("S-BLOCK-ON-PLANE", repr(sim))


if __name__ == "__main__":
    unittest.main()

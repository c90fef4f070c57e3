"""polydem.cut_rock_mass and scenes with a [[rock_mass]]: volumes, determinism, errors, a run.

Run by ctest (python_rock_mass) with PYTHONPATH=build/python and /usr/bin/python3.
"""
import importlib.util
import os
import tempfile
import unittest

import numpy as np

import polydem

SCENE = """\
[scene]
id = "T-PY-ROCK"

[simulation]
dt = "2e-4 s"
steps = 50

[[material]]
name = "rock"
density = 2600
kn = "1 GN/m"
ks = "0.5 GN/m"
friction_angle = 30

[[rock_mass]]
name = "slope"
material = "rock"
region = { type = "box", min = [0, 0, 0], max = [6, 3, 4] }

[[rock_mass.plane]]
name = "base"
dip = 20
dip_direction = 90
point = [3, 0, 1]
fixed = "below"

[[rock_mass.joint_set]]
name = "J1"
dip = 85
dip_direction = 270
spacing = 1.5
"""

REGION = {"type": "box", "min": [0, 0, 0], "max": [5, 4, 3]}
SETS = [{"name": "J1", "dip": 70, "dip_direction": 110, "spacing": 1.2, "spacing_jitter": 0.2,
         "orientation_jitter": 5, "seed": 3},
        {"name": "J2", "dip": 20, "dip_direction": 300, "spacing": 1.0}]


class CutRockMass(unittest.TestCase):
    def test_volumes_sum_to_the_region(self):
        m = polydem.cut_rock_mass(REGION, SETS, min_volume=0.02)
        self.assertGreater(len(m["vertices"]), 20)
        self.assertAlmostEqual(m["volume"].sum(), 60.0, delta=1e-10 * 60)
        self.assertGreaterEqual(m["report"]["smallest_volume"], 0.02)
        for v, vol in zip(m["vertices"], m["volume"]):
            self.assertAlmostEqual(polydem.ConvexPolyhedron(v).volume, vol, delta=1e-12 * vol)
        self.assertEqual(m["sides"].shape, (len(m["vertices"]), len(m["plane_names"])))

    def test_same_bits_every_time(self):
        a = polydem.cut_rock_mass(REGION, SETS)
        b = polydem.cut_rock_mass(REGION, SETS)
        self.assertEqual(len(a["vertices"]), len(b["vertices"]))
        for u, v in zip(a["vertices"], b["vertices"]):
            self.assertTrue(np.array_equal(u, v))

    def test_fixed_side_and_profile(self):
        region = {"type": "profile", "profile": [(0, 0), (10, 0), (10, 2), (6, 6), (0, 6)],
                  "y": (0, 2)}
        plane = {"name": "base", "dip": 30, "dip_direction": 90, "point": (5, 0, 2),
                 "fixed": "below"}
        m = polydem.cut_rock_mass(region, [], [plane])
        self.assertEqual(m["report"]["fixed_blocks"] + m["report"]["free_blocks"],
                         len(m["vertices"]))
        normal = np.array([np.sin(np.radians(30)), 0, np.cos(np.radians(30))])
        for c, fixed in zip(m["centroid"], m["fixed"]):
            self.assertEqual(bool(fixed), normal @ (c - np.array([5, 0, 2])) < 0)

    def test_errors(self):
        with self.assertRaises(ValueError):
            polydem.cut_rock_mass(REGION, [{"name": "J", "dip": 40, "dip_direction": 0,
                                            "spacing": 1, "spacnig": 2}])
        with self.assertRaises(polydem.GeometryError):
            polydem.cut_rock_mass(REGION, [{"name": "J", "dip": 40, "dip_direction": 0,
                                            "spacing": -1}])
        with self.assertRaises(ValueError):
            polydem.cut_rock_mass({"type": "sphere"})
        # max_blocks is the limit the estimate is held to (default a million).
        with self.assertRaisesRegex(polydem.GeometryError, "more than the limit of 5"):
            polydem.cut_rock_mass(REGION, SETS, max_blocks=5)
        with self.assertRaises(ValueError):
            polydem.cut_rock_mass(REGION, SETS, max_blocks=0)


class SceneWithRockMass(unittest.TestCase):
    def test_blocks_and_a_run(self):
        polydem.set_log_level("warning")
        scene = polydem.parse_scene(SCENE, "rock.toml")
        info = scene.rock_masses[0]
        self.assertEqual(info["name"], "slope")
        self.assertEqual(info["blocks"], scene.num_particles)
        self.assertEqual(scene.particles["label"][0], "slope_0")
        self.assertEqual(int(scene.particles["fixed"].sum()), info["report"]["fixed_blocks"])
        result = polydem.run(scene)
        self.assertEqual(result["steps"], 50)

    def test_error_has_file_and_line(self):
        with self.assertRaises(polydem.InputError) as e:
            polydem.parse_scene(SCENE.replace("spacing = 1.5", "spacing = 0"), "rock.toml")
        self.assertEqual(e.exception.file, "rock.toml")
        self.assertEqual(e.exception.line, SCENE.splitlines().index("spacing = 1.5") + 1)


class Joints(unittest.TestCase):
    def test_contacts_on_a_joint_take_it(self):
        """A rock mass built in Python with a joint on its bedding: after a run, the contacts
        that took the joint (Simulation.contacts()["joint"]) lie on the bedding, and others on
        the steep set, which names no joint, take none."""
        s = polydem.Scene("joints", dt=2e-5, steps=300)
        s.add_material("rock", density=2600, kn=1e9, ks=5e8, friction_angle=20,
                       local_damping=0.7)
        s.add_joint("bedding", jkn="10 GPa/m", jks="5 GPa/m", friction_angle=30,
                    cohesion="20 kPa")
        s.add_rock_mass("m", "rock", region={"type": "box", "min": (0, 0, 0), "max": (4, 3, 3)},
                        joint_sets=[{"name": "B", "dip": 10, "dip_direction": 90,
                                     "spacing": 1.2, "joint": "bedding"},
                                    {"name": "J", "dip": 60, "dip_direction": 0,
                                     "spacing": 1.7}],
                        planes=[{"name": "base", "dip": 0, "dip_direction": 0,
                                 "point": (0, 0, 0.5), "fixed": "below"}])
        self.assertIn('joint = "bedding"', s.to_toml())
        sim = polydem.Simulation(s)
        sim.run()
        c = sim.contacts()
        self.assertEqual(c["joint"].dtype, np.int32)
        bedding = np.array(
            [np.sin(np.radians(10)), 0.0, np.cos(np.radians(10))])
        steep = np.array([0.0, np.sin(np.radians(60)), np.cos(np.radians(60))])
        on_joint = c["joint"] == 0
        self.assertGreater(on_joint.sum(), 3)
        self.assertTrue(np.all(np.abs(c["normal"][on_joint] @ bedding) > 1 - 1e-6))
        on_steep = np.abs(c["normal"] @ steep) > 1 - 1e-6
        self.assertTrue(np.all(c["joint"][on_steep] == -1))
        self.assertTrue(set(np.unique(c["joint"])) <= {-1, 0})

    def test_joint_units_are_checked_when_added(self):
        s = polydem.Scene("joints", dt=1e-4, steps=1)
        with self.assertRaisesRegex(ValueError, r"jkn: expected a stiffness per area \(Pa/m\)"):
            s.add_joint("j", jkn="1 GN/m", jks=1e9, friction_angle=30)
        s.add_joint("j", jkn=1e9, jks=1e9, friction_angle=30, cohesion="50 kPa")
        self.assertIn('cohesion = "50 kPa"', s.to_toml())

    def test_each_law_takes_its_own_parameters(self):
        """add_joint reads a law's parameters from the law's declaration (the scene reader's):
        a Barton-Bandis joint with JRC, JCS in engineers' units and dilation; a key of another
        law and a value outside its range are refused."""
        s = polydem.Scene("joints", dt=1e-4, steps=1)
        s.add_joint("fault", law="barton-bandis", jkn="1 GPa/m", jks="0.5 GPa/m", jrc=12,
                    jcs="80 MPa", residual_friction_angle=28, dilation=True)
        s.add_joint("bedding", law="coulomb-residual", jkn=1e9, jks=1e9, friction_angle=35,
                    cohesion="50 kPa", residual_friction_angle=25)
        toml = s.to_toml()
        self.assertIn('law = "barton-bandis"', toml)
        self.assertIn('jcs = "80 MPa"', toml)
        self.assertIn("dilation = true", toml)
        self.assertIn("residual_friction_angle = 25", toml)
        with self.assertRaisesRegex(ValueError, r"jrc.*\[0, 20\]"):
            s.add_joint("rough", law="barton-bandis", jkn=1e9, jks=1e9, jrc=25, jcs=1e8,
                        residual_friction_angle=28)
        with self.assertRaisesRegex(ValueError, r"jrc"):
            s.add_joint("plain", jkn=1e9, jks=1e9, friction_angle=30, jrc=5)
        with self.assertRaisesRegex(ValueError, r"law"):
            s.add_joint("other", law="mohr", jkn=1e9, jks=1e9, friction_angle=30)

    def test_unknown_joint_is_an_input_error(self):
        s = polydem.Scene("joints", dt=1e-4, steps=1)
        s.add_material("rock", density=2600, kn=1e9)
        with self.assertRaisesRegex(ValueError, r"no \[\[joint\]\] is named 'nowhere'"):
            s.add_rock_mass("m", "rock", region={"type": "box", "min": (0, 0, 0),
                                                 "max": (2, 2, 2)},
                            planes=[{"name": "p", "dip": 10, "dip_direction": 0,
                                     "point": (1, 1, 1), "joint": "nowhere"}])


class PlotRockMass(unittest.TestCase):
    def test_writes_a_png(self):
        source = os.environ.get("POLYDEM_SOURCE_DIR",
                                os.path.join(os.path.dirname(__file__), os.pardir, os.pardir))
        spec = importlib.util.spec_from_file_location(
            "plot_rock_mass", os.path.join(source, "python_coupling", "plots", "plot_rock_mass.py"))
        plot = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(plot)
        with tempfile.TemporaryDirectory() as work:
            scene = os.path.join(work, "rock.toml")
            with open(scene, "w") as f:
                f.write(SCENE)
            png = plot.plot(scene, os.path.join(work, "rock.png"))
            with open(png, "rb") as f:
                self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")


if __name__ == "__main__":
    unittest.main()

"""[[bolt]] from Python: Scene.add_bolt writes the bolt the reader reads (SceneData.bolts, the
direction from trend and plunge), bad keys are refused at once with the bolt's name, a bolt that
crosses no joint is refused when the simulation is built (file, line and name), and a pretensioned
bolt pulls a free block towards the fixed block it is anchored in with its pretension: with no
gravity, the block's velocity along the bolt grows at P / m.
"""
import math
import os
import unittest

import numpy as np

import polydem

polydem.set_log_level("warning")
SCENES = os.path.join(os.environ["POLYDEM_SOURCE_DIR"], "benchmark_scenes")


def two_cubes(dt=1e-3, steps=40):
    """A fixed 1 m cube at the origin and a free one 0.5 m above it, no gravity."""
    s = polydem.Scene("bolt-pull", dt=dt, steps=steps, gravity=(0, 0, 0))
    s.add_material("rock", density=2650, kn=1e9, ks=5e8, friction_angle=30)
    s.add_shape("cube", box=(1, 1, 1))
    s.add_particle("cube", "rock", position=(0, 0, 0), fixed=True, label="rock")
    s.add_particle("cube", "rock", position=(0, 0, 1.5), label="block")
    return s


class Bolts(unittest.TestCase):
    def test_settings_read_and_written(self):
        s = polydem.Scene.load(os.path.join(SCENES, "B-BOLTED-BLOCK.toml"))
        [b] = s.build().bolts
        self.assertEqual(b["name"], "B1")
        self.assertEqual((b["length"], b["axial_stiffness"], b["axial_yield"]), (2.0, 2e6, 5e3))
        self.assertEqual((b["shear_stiffness"], b["pretension"]), (0.0, 0.0))
        self.assertIsNone(b["ultimate_elongation"])
        # trend 270, plunge 30: west and down
        c = math.cos(math.radians(30))
        np.testing.assert_allclose(b["direction"], [-c, 0, -0.5], atol=1e-15)
        s.add_bolt("B2", start=(0, 0, 1), direction=(0, 0, -2), length="3 m",
                   axial_stiffness="1 MN/m", axial_yield="100 kN", pretension="20 kN",
                   ultimate_elongation="5 cm")
        again = polydem.Scene.from_toml(s.to_toml()).build().bolts
        self.assertEqual([x["name"] for x in again], ["B1", "B2"])
        self.assertEqual(again[1]["direction"], [0.0, 0.0, -1.0])
        self.assertEqual((again[1]["pretension"], again[1]["ultimate_elongation"]), (2e4, 0.05))

    def test_bad_bolts_name_the_bolt_and_key(self):
        s = two_cubes()
        with self.assertRaisesRegex(ValueError, r"add_bolt\('B1'\).*pretension.*axial_yield"):
            s.add_bolt("B1", start=(0, 0, 1.8), direction=(0, 0, -1), length=2,
                       axial_stiffness=1e6, axial_yield=1e3, pretension=2e3)
        with self.assertRaisesRegex(ValueError, r"add_bolt\('B1'\).*direction"):
            s.add_bolt("B1", start=(0, 0, 1.8), direction=(0, 0, -1), trend=0, plunge=90,
                       length=2, axial_stiffness=1e6, axial_yield=1e3)
        with self.assertRaisesRegex(ValueError, r"add_bolt\('B1'\).*plunge"):
            s.add_bolt("B1", start=(0, 0, 1.8), trend=0, length=2, axial_stiffness=1e6,
                       axial_yield=1e3)
        with self.assertRaisesRegex(ValueError, r"add_bolt\('B1'\).*axial_stiffness"):
            s.add_bolt("B1", start=(0, 0, 1.8), trend=0, plunge=90, length=2,
                       axial_stiffness=-1, axial_yield=1e3)
        # Accepted by the reader, but it lies in the free block only: no joint to hold.
        s.add_bolt("short", start=(0, 0, 1.8), trend=0, plunge=90, length=0.5,
                   axial_stiffness=1e6, axial_yield=1e3)
        with self.assertRaisesRegex(polydem.InputError,
                                    r":\d+: \[\[bolt\]\] 'short'.*one block only"):
            polydem.Simulation(s.build())

    def test_pretension_pulls_the_block(self):
        dt, n, pull = 1e-3, 40, 2650.0  # N: 1 m/s^2 on a 1 m cube of 2650 kg/m^3
        s = two_cubes(dt, n)
        s.add_bolt("B1", start=(0, 0, 1.8), trend=0, plunge=90, length=2,
                   axial_stiffness="1 N/m", axial_yield="10 kN", shear_stiffness="1 N/m",
                   shear_yield="1 kN", pretension=pull)
        sim = polydem.Simulation(s.build())
        sim.run()
        p = sim.particles()
        v = p["velocity"][list(p["uid"]).index(2)]
        # Down the bolt at P / m; the 1 N/m springs change it by less than 1e-9 over the run.
        expected = np.array([0.0, 0.0, -pull / 2650.0 * (sim.time - dt / 2)])
        np.testing.assert_allclose(v, expected, rtol=1e-6, atol=1e-12)


if __name__ == "__main__":
    unittest.main()

"""[water] from Python: Scene.set_water / Scene.water set and read the settings, the built scene
(SceneData.water) holds them in SI units, bad settings are refused by the reader with the line,
and the water lifts a block: a block on a horizontal joint under a level 1.5 times its weight's
head starts to rise at g / 2 (the uplift gamma_w h A on its base, the only joint face it has; its
top and sides are the region's faces and carry none), and as its base rises the uplift falls by
gamma_w A per metre: m z'' = gamma_w A (h - z) - W, a harmonic motion, v = (g / 2) sin(w t) / w
with w^2 = gamma_w A / m. The same level given as a surface through five points lifts it alike;
with the base joint dry ([[water.joint]], set_water(joint=...)) it moves as with no water at all.
"""
import math
import os
import unittest

import polydem

polydem.set_log_level("warning")
G = 9.81
RHO = 2600.0
SCENES = os.path.join(os.environ["POLYDEM_SOURCE_DIR"], "benchmark_scenes")


def block_on_joint(level):
    """A 2 x 2 x 1 m block on the fixed rock below the horizontal plane z = 0."""
    s = polydem.Scene("uplift", dt=1e-4, steps=200, gravity=(0, 0, -G))
    s.add_material("rock", density=RHO, kn=1e9, ks=5e8, friction_angle=30)
    s.add_rock_mass("mass", "rock", {"type": "box", "min": (-1, -1, -1), "max": (1, 1, 1)},
                    planes=[{"name": "base", "dip": 0, "dip_direction": 0, "point": (0, 0, 0),
                             "fixed": "below"}])
    s.set_water(unit_weight="9810 N/m^3", level=level)
    return s


class Water(unittest.TestCase):
    def test_settings_read_and_written(self):
        s = polydem.Scene.load(os.path.join(SCENES, "W-PLANAR-CRACK.toml"))
        self.assertEqual(len(s.water["points"]), 3)
        built = s.build().water
        self.assertEqual(built["unit_weight"], 9810.0)
        self.assertEqual(built["points"], [(0.0, -1.0), (0.0, 1.0), (3.0, 0.0)])
        self.assertEqual(built["times"], [0.0])
        self.assertEqual(built["heights"][0][:2], [1.0, 1.0])
        s.set_water(unit_weight="10 kN/m^3")
        self.assertEqual(s.build().water["unit_weight"], 10000.0)
        s.water = {"level": "2 m", "unit_weight": 9810}
        self.assertEqual(s.build().water["points"], [])
        self.assertEqual(s.build().water["heights"], [[2.0]])
        s.water = None
        self.assertIsNone(s.water)
        self.assertIsNone(s.build().water)

    def test_bad_settings_name_the_key(self):
        s = block_on_joint(1.0)
        s.set_water(points=[[0, 0, 1], [1, 0, 1], [2, 0, 1]])  # and level: two surfaces
        with self.assertRaisesRegex(polydem.InputError, r"\[water\] level"):
            s.build()
        s.set_water(level=None)
        with self.assertRaisesRegex(polydem.InputError, "one line in plan"):
            s.build()
        s.set_water(points=None, unit_weight="9810 N/m^2")
        with self.assertRaisesRegex(polydem.InputError, "unit_weight"):
            s.build()
        s.set_water(unit_weight=9810, level=None, table=[[1, 0.5], [0.5, 1.0]])
        with self.assertRaisesRegex(polydem.InputError, "times must increase"):
            s.build()

    def test_surface_through_points_and_joints(self):
        s = block_on_joint(1.0)
        corners = [[-1, -1, 1.0], [1, -1, 1.0], [1, 1, 1.5], [-1, 1, 1.5], [0, 0, 2.0]]
        s.set_water(level=None, points=corners, joint=[{"joint": "base", "dry": True}])
        built = s.build().water
        self.assertEqual(len(built["points"]), 5)
        self.assertEqual(len(built["triangles"]), 4)
        self.assertEqual(built["heights"], [[1.0, 1.0, 1.5, 1.5, 2.0]])
        self.assertEqual([(j["joint"], j["dry"]) for j in built["joints"]], [("base", True)])
        s.set_water(points=[[-1, -1], [1, -1], [1, 1], [-1, 1]], table=[[0, 1, 1, 2, 2]])
        self.assertEqual(s.build().water["heights"], [[1.0, 1.0, 2.0, 2.0]])
        s.set_water(table=[[0, 1, 1, 2]])
        with self.assertRaisesRegex(polydem.InputError, r"\[water\] table\[0\].*z1 \.\. z4"):
            s.build()
        s.set_water(table=None, points=None, joint=[{"joint": "bedding", "level": 1.0}])
        with self.assertRaisesRegex(polydem.InputError, r"\[\[water.joint\]\] #1 joint.*'bedding'"):
            s.build()
        s.set_water(points=[[0, 0, 1], [1, 0, 1], [0, 1, 1], [1, 0, 2]], joint=None)
        with self.assertRaisesRegex(polydem.InputError, "points 2 and 4 lie at one place"):
            s.build()

    def run_block(self, scene):
        sim = polydem.Simulation(scene.build())
        sim.run()
        p = sim.particles()
        free = [i for i, f in enumerate(p["flags"]) if not f & polydem.FLAG_FIXED]
        self.assertEqual(len(free), 1)
        return sim, p["velocity"][free[0], 2]

    def test_surface_through_points_lifts_like_the_level(self):
        gamma_w, area, mass = 9810.0, 4.0, RHO * 4.0
        level = 1.5 * RHO * G * 1.0 / gamma_w
        s = block_on_joint(level)
        # The level as a surface through five points (four triangles), over the block and beyond.
        s.set_water(level=None, points=[[-2, -2, level], [2, -2, level], [2, 2, level],
                                        [-2, 2, level], [0.3, -0.2, level]])
        sim, vz = self.run_block(s)
        t = sim.time - 0.5 * sim.dt
        w = math.sqrt(gamma_w * area / mass)
        expected = 0.5 * G * math.sin(w * t) / w
        self.assertAlmostEqual(vz, expected, delta=1e-6 * expected)
        # The base drained: no water force at all, the same bits as without water.
        s.set_water(joint=[{"joint": "base", "dry": True}])
        _, vz_dry = self.run_block(s)
        s.water = None
        _, vz_none = self.run_block(s)
        self.assertEqual(vz_dry, vz_none)
        self.assertLess(vz_dry, 0.5 * expected)

    def test_uplift_lifts_a_block(self):
        # gamma_w h A = 1.5 rho g (1 m) A: the block starts to rise at g / 2.
        gamma_w, area, mass = 9810.0, 4.0, RHO * 4.0
        level = 1.5 * RHO * G * 1.0 / gamma_w
        sim = polydem.Simulation(block_on_joint(level).build())
        sim.run()
        p = sim.particles()
        free = [i for i, f in enumerate(p["flags"]) if not f & polydem.FLAG_FIXED]
        self.assertEqual(len(free), 1)
        vz = p["velocity"][free[0], 2]
        t = sim.time - 0.5 * sim.dt  # the leapfrog's velocities are at t - dt/2
        w = math.sqrt(gamma_w * area / mass)
        expected = 0.5 * G * math.sin(w * t) / w
        self.assertAlmostEqual(vz, expected, delta=1e-6 * expected)
        self.assertGreater(0.5 * G * t - vz, 1e-4 * vz)  # the falling uplift is seen


if __name__ == "__main__":
    unittest.main()

"""[seismic] from Python: Scene.set_seismic / Scene.seismic set and read the pseudo-static
coefficients, the built scene (SceneData.seismic) holds them, bad settings are refused by the
reader with the key, and the load has the documented directions: a block in free fall under
kh = 0.3 at azimuth 30 deg and kv = 0.2 accelerates at gravity + g (kh (sin 30, cos 30, 0) +
kv (0, 0, 1)) (azimuth clockwise from north = +y, kv positive upward).
"""
import math
import os
import unittest

import numpy as np

import polydem

polydem.set_log_level("warning")
G = 9.81
SCENES = os.path.join(os.environ["POLYDEM_SOURCE_DIR"], "benchmark_scenes")


def falling_block(dt=1e-3, steps=40):
    s = polydem.Scene("seismic-fall", dt=dt, steps=steps, gravity=(0, 0, -G))
    s.add_material("rock", density=2650, kn=1e9, ks=5e8, friction_angle=30)
    s.add_shape("cube", box=(1, 1, 1))
    s.add_particle("cube", "rock", position=(0, 0, 10), label="block")
    return s


class Seismic(unittest.TestCase):
    def test_settings_read_and_written(self):
        s = polydem.Scene.load(os.path.join(SCENES, "E-PSEUDO-STATIC.toml"))
        self.assertEqual(s.seismic, {"kh": 0.2, "azimuth": 90, "kv": 0})
        built = s.build().seismic
        self.assertEqual((built["kh"], built["azimuth"], built["kv"]), (0.2, 90.0, 0.0))
        s.set_seismic(kv=-0.1)
        self.assertEqual(s.build().seismic["kv"], -0.1)
        s.seismic = {"kv": 0.05}
        self.assertEqual(s.build().seismic["kh"], 0.0)
        self.assertEqual(polydem.Scene.from_toml(s.to_toml()).build().seismic["kv"], 0.05)
        s.seismic = None
        self.assertIsNone(s.seismic)
        self.assertIsNone(s.build().seismic)

    def test_bad_settings_name_the_key(self):
        s = falling_block()
        s.set_seismic(kh=1.5, azimuth=90)
        with self.assertRaisesRegex(polydem.InputError, r"\[seismic\] kh.*\[0, 1\]"):
            s.build()
        s.set_seismic(kh=-0.1)
        with self.assertRaisesRegex(polydem.InputError, r"\[seismic\] kh"):
            s.build()
        s.set_seismic(kh=0.1, azimuth=None)
        with self.assertRaisesRegex(polydem.InputError, r"\[seismic\] kh.*azimuth"):
            s.build()
        s.set_seismic(azimuth=360)
        with self.assertRaisesRegex(polydem.InputError, r"\[seismic\] azimuth"):
            s.build()
        with self.assertRaisesRegex(TypeError, "kz"):  # the builder knows the keys too
            s.set_seismic(kz=0.1)
        s.seismic = None
        bad = s.to_toml() + "\n[seismic]\nkh = 0.1\nazimuth = 0\nky = 0.2\n"
        with self.assertRaisesRegex(polydem.InputError, r":\d+.*ky"):
            polydem.Scene.from_toml(bad).build()

    def test_load_directions(self):
        dt, n = 1e-3, 40
        kh, azimuth, kv = 0.3, 30.0, 0.2
        s = falling_block(dt, n)
        s.set_seismic(kh=kh, azimuth=azimuth, kv=kv)
        sim = polydem.Simulation(s.build())
        sim.run()
        v = sim.particles()["velocity"][0]
        a = math.radians(azimuth)
        expected = np.array([G * kh * math.sin(a), G * kh * math.cos(a), -G + G * kv])
        # The leapfrog's velocities are at t - dt/2 and integrate a constant load exactly.
        np.testing.assert_allclose(v, expected * (sim.time - dt / 2), rtol=1e-12)


if __name__ == "__main__":
    unittest.main()

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


class Record(unittest.TestCase):
    """[seismic] record from Python: Scene.load makes the record's path absolute, the built scene
    holds the samples in m/s^2, and a fixed body moves with the ground the record integrates to."""

    def test_loaded_scene_keeps_its_record(self):
        s = polydem.Scene.load(os.path.join(SCENES, "E-NEWMARK.toml"))
        self.assertEqual(s.seismic["record"], os.path.join(SCENES, "E-NEWMARK.csv"))
        built = polydem.Scene.from_toml(s.to_toml()).build().seismic
        rows = np.loadtxt(os.path.join(SCENES, "E-NEWMARK.csv"), delimiter=",", skiprows=5)
        np.testing.assert_array_equal(built["record_time"], rows[:, 0])
        np.testing.assert_allclose(built["record_acceleration"], G * rows[:, 1:4], rtol=1e-15)

    def test_fixed_body_moves_with_the_ground(self):
        import tempfile
        a = np.array([0.0, 2.0, -0.5])  # m/s^2, constant from t = 0 to 1 s
        dt, n = 1e-3, 40
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "constant.csv")
            with open(path, "w") as f:
                f.write("time,ax,ay,az\n0,%r,%r,%r\n1,%r,%r,%r\n" % (tuple(a) * 2))
            s = falling_block(dt, n)
            s.add_particle("cube", "rock", position=(0, 0, 0), fixed=True, label="ground")
            s.set_seismic(record=path, scale=1.0)
            self.assertEqual(s.build().seismic["record_file"], path)
            sim = polydem.Simulation(s.build())
        sim.run()
        p = sim.particles()
        ground = list(p["uid"]).index(2)
        t = sim.time
        # u = a t^2 / 2 exactly for a constant acceleration; the velocity is taken at t - dt/2.
        np.testing.assert_allclose(p["position"][ground], a * t * t / 2, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(p["velocity"][ground], a * (t - dt / 2), rtol=1e-12)


if __name__ == "__main__":
    unittest.main()

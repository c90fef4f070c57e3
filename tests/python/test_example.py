"""python_coupling/examples/tilt_and_plot.py, run as a user would (its main() with --out), on the
scene beside it: the files it writes exist and agree with the run, and the block behaves as
Coulomb friction says while it sticks.

The tilt test: a cube on a platform tilting at w = 10 deg/s about y, friction angle phi = 30 deg.
A rigid block sticks while tan(theta) < tan(phi) and turns with the platform; past phi it slides.
The sliding phase itself (slip s(theta) of the example's docstring) is printed, not asserted: the
lp kernel of the scene slides more slowly than the rigid-block law (about 5 mm at 36 deg against
71 mm), which is a finding about the contact model, not about the Python layer.

Run by ctest with PYTHONPATH=build/python and /usr/bin/python3: python_example on one rank,
python_example_np2 under mpiexec -n 2 (every rank runs the scene, rank 0 writes and plots; the
other ranks skip the checks, which read rank 0's files).
"""
import importlib.util
import json
import math
import os
import shutil
import struct
import unittest

import numpy as np

import polydem

EXAMPLES = os.path.join(os.environ["POLYDEM_SOURCE_DIR"], "python_coupling", "examples")
WORK = os.environ.get("POLYDEM_TEST_WORK", "/tmp/polydem_python_test")


def load_example():
    spec = importlib.util.spec_from_file_location(
        "tilt_and_plot", os.path.join(EXAMPLES, "tilt_and_plot.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def png_size(path):
    """(width, height) from the IHDR chunk; ValueError if the file is not a PNG."""
    with open(path, "rb") as f:
        head = f.read(24)
    if head[:8] != b"\x89PNG\r\n\x1a\n" or head[12:16] != b"IHDR":
        raise ValueError(path + " is not a PNG file")
    return struct.unpack(">II", head[16:24])


class TiltExample(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        polydem.set_log_level("warning")
        cls.example = load_example()
        cls.out = os.path.join(WORK, "tilt_example_np%d" % polydem.mpi_size())
        if polydem.mpi_rank() == 0:
            shutil.rmtree(cls.out, ignore_errors=True)  # before the run's first collective call
        cls.scene = polydem.read_scene(os.path.join(EXAMPLES, "tilt_table.toml"))
        cls.r = cls.example.main(["--out", cls.out])

    def setUp(self):
        if polydem.mpi_rank() != 0:
            self.skipTest("rank 0 writes and checks the example's outputs")

    def test_files_agree_with_the_run(self):
        for name in ("series.csv", "summary.json", "tilt.png"):
            self.assertTrue(os.path.isfile(os.path.join(self.out, name)), name)
        for name in ("snapshots.pvd", "snapshots.xmf"):
            self.assertFalse(os.path.exists(os.path.join(self.out, name)), name)
        with open(os.path.join(self.out, "summary.json")) as f:
            summary = json.load(f)
        self.assertEqual(summary["state_hash"], self.r["state_hash"])
        self.assertEqual(summary["steps"], self.r["steps"])
        # The scene stops at end_time: that many steps of dt, the last series row at that time.
        self.assertEqual(self.r["steps"], round(self.scene.end_time / self.scene.dt))
        _, series = polydem.plots.read_series(os.path.join(self.out, "series.csv"))
        self.assertEqual(series["time"][-1], self.r["time"])
        self.assertEqual(len(series["time"]), len(self.r["theta"]))
        # The platform turns at |w| from t = 0: theta = |w| t, up to the final tilt.
        rate = np.linalg.norm(self.scene.drivers[0]["angular_velocity"])
        np.testing.assert_allclose(self.r["theta"], rate * series["time"], rtol=1e-12, atol=0)
        # The figure the example saves: figsize (7.5, 6.5) inches at 150 dpi.
        self.assertEqual(self.r["png"], os.path.join(self.out, "tilt.png"))
        self.assertEqual(png_size(self.r["png"]), (round(7.5 * 150), round(6.5 * 150)))

    def test_block_sticks_below_the_friction_angle(self):
        phi = math.radians(self.scene.materials[0]["friction_angle"])
        self.assertAlmostEqual(self.r["friction_angle_deg"], math.degrees(phi), delta=1e-12)
        theta, slip = self.r["theta"], self.r["slip"]
        sticking = theta < phi
        self.assertGreater(np.count_nonzero(sticking), 100)
        # Below phi the block neither slides (the example's threshold ONSET_SLIP) nor rocks: it
        # turns with the platform, by less than the angle that would move its centroid (half an
        # edge above the contact face) by ONSET_SLIP.
        self.assertLess(slip[sticking].max(), self.example.ONSET_SLIP)
        half_edge = 0.5 * np.ptp(self.scene.shapes[1]["vertices"][:, 2])
        rocking = np.abs(self.r["rotation"][sticking] - theta[sticking]).max()
        self.assertLess(rocking, self.example.ONSET_SLIP / half_edge)
        # The analytical slip is 0 below phi.
        np.testing.assert_array_equal(self.r["analytic"][sticking], 0.0)

    def test_block_slides_past_the_friction_angle(self):
        onset, phi_deg = self.r["onset_deg"], self.r["friction_angle_deg"]
        self.assertGreater(onset, phi_deg)
        self.assertLessEqual(onset, math.degrees(self.r["theta"][-1]))
        self.assertGreater(self.r["slip"][-1], self.example.ONSET_SLIP)
        print("onset of sliding %.3f deg (rigid block %.3f deg); final slip %.4g m (rigid block "
              "%.4g m)" % (onset, self.r["onset_analytic_deg"], self.r["slip"][-1],
                           self.r["analytic"][-1]))


if __name__ == "__main__":
    unittest.main()

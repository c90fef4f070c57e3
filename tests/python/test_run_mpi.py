"""polydem on two ranks (mpiexec -n 2 python3 test_run_mpi.py): runs and stepped simulations over
MPI_COMM_WORLD give the state hash of the one-rank `polydem run` (fixture python_reference_run),
and particles(gather=True) shows every particle once on every rank.

Every rank runs the same tests in the same order, and each test makes all its collective calls
before its first assertion, so that a failure on one rank cannot leave the other waiting; mpiexec
exits non-zero when a test failed on any rank.
"""
import json
import os
import unittest

import numpy as np

import polydem

SCENE = os.environ["POLYDEM_REFERENCE_SCENE"]
END_TIME = float(os.environ["POLYDEM_REFERENCE_END_TIME"])


def reference_hash():
    with open(os.path.join(os.environ["POLYDEM_REFERENCE_RUN"], "summary.json")) as f:
        return json.load(f)["state_hash"]


class TwoRanks(unittest.TestCase):
    def test_world(self):
        self.assertEqual(polydem.mpi_size(), 2)
        self.assertIn(polydem.mpi_rank(), (0, 1))

    def test_run_gives_the_one_rank_hash(self):
        r = polydem.run(SCENE, end_time=END_TIME)
        self.assertEqual(r["state_hash"], reference_hash())
        self.assertTrue(r["all_checks_pass"])

    def test_stepping_gives_the_one_rank_hash(self):
        scene = polydem.read_scene(SCENE)
        scene.end_time = END_TIME
        sim = polydem.Simulation(scene)
        sim.step(round(END_TIME / sim.dt))
        state_hash = sim.state_hash()
        everything = sim.particles(gather=True)
        m = sim.monitors()
        local = sim.particles()

        self.assertEqual(state_hash, reference_hash())
        np.testing.assert_array_equal(everything["uid"], [1, 2])
        np.testing.assert_array_equal(everything["flags"], [polydem.FLAG_FIXED, 0])
        self.assertEqual(everything["position"].shape, (2, 3))
        # Local view: the fixed base is on every rank, the cube on its owner only.
        self.assertIn(1, local["uid"].tolist())
        self.assertTrue(set(local["uid"].tolist()) <= {1, 2})
        if 2 in local["uid"].tolist():
            i = local["uid"].tolist().index(2)
            np.testing.assert_array_equal(local["position"][i], everything["position"][1])
        self.assertEqual((m["particles"], m["contacts"]), (1, 1))


if __name__ == "__main__":
    unittest.main()

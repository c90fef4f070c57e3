"""Simulation.add_force_operator: a Python force added to every step.

A cube falls freely under gravity; an operator lifts it with half its weight, so it falls at g/2.
The leapfrog integrates a constant acceleration exactly, so its drop after n steps is
(g/2) t^2 / 2 to rounding. An operator returning zero forces leaves the state hash unchanged.
"""
import os
import unittest

import numpy as np

import polydem

SCENE = os.path.join(os.environ["POLYDEM_SOURCE_DIR"], "tests", "python", "free_fall.toml")
G = 9.81
MASS = 2650.0  # 1 m^3 of rock


class ForceOperator(unittest.TestCase):
    def test_uplift_halves_the_fall(self):
        sim = polydem.Simulation(SCENE)
        calls = []

        def uplift(time, dt, particles):
            calls.append((time, dt))
            self.assertEqual(particles["position"].shape, (len(particles["uid"]), 3))
            np.testing.assert_allclose(particles["mass"], MASS, rtol=1e-12)
            forces = np.zeros((len(particles["uid"]), 3))
            forces[:, 2] = 0.5 * G * particles["mass"]
            return forces

        sim.add_force_operator("uplift", uplift)
        self.assertEqual(sim.force_operators, ["uplift"])
        sim.run()
        t = sim.time
        self.assertAlmostEqual(t, 0.05, delta=1e-12)
        z = sim.particles()["position"][0, 2]
        expected = 0.5 * (0.5 * G) * t * t
        self.assertAlmostEqual(5.0 - z, expected, delta=1e-9 * expected)
        # Called when added (t = 0: its share of the leapfrog's start) and once per step.
        self.assertEqual(len(calls), 501)
        self.assertEqual(calls[0], (0.0, 1e-4))

    def test_zero_force_changes_no_bit(self):
        plain = polydem.Simulation(SCENE)
        plain.run()
        zero = polydem.Simulation(SCENE)
        zero.add_force_operator("nothing", lambda t, dt, p: np.zeros((len(p["uid"]), 3)))
        zero.run()
        self.assertEqual(plain.state_hash(), zero.state_hash())

    def test_misuse_is_reported(self):
        sim = polydem.Simulation(SCENE)
        with self.assertRaises(TypeError):
            sim.add_force_operator("not callable", 3)
        sim.add_force_operator("once", lambda t, dt, p: None)
        with self.assertRaisesRegex(Exception, "already added"):
            sim.add_force_operator("once", lambda t, dt, p: None)
        # Before the first step an operator is called at once (its share of the leapfrog start):
        # a wrong result is reported there, and the operator is not added.
        with self.assertRaisesRegex(ValueError, "returned 5 forces for 1 particles"):
            sim.add_force_operator("wrong shape", lambda t, dt, p: np.zeros((5, 3)))
        self.assertEqual(sim.force_operators, ["once"])

        def fails(t, dt, p):
            raise RuntimeError("user error")

        sim.step()
        sim.add_force_operator("fails", fails)
        with self.assertRaisesRegex(RuntimeError, "user error"):
            sim.step()

if __name__ == "__main__":
    unittest.main()

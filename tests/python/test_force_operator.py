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
    def test_an_operator_cannot_step_or_change_the_simulation(self):
        # Each call that would step, change or checkpoint the simulation from inside its own
        # step is refused, naming the operator; the run goes on as if none had been tried.
        os.makedirs(os.environ["POLYDEM_TEST_WORK"], exist_ok=True)
        path = os.path.join(os.environ["POLYDEM_TEST_WORK"], "force_operator_reentrant.h5")
        if os.path.exists(path):
            os.remove(path)
        sim = polydem.Simulation(SCENE)
        attempts = [lambda: sim.step(), sim.run, sim.run_equilibrium,
                    lambda: sim.set_velocity(1, velocity=(1, 0, 0)),
                    lambda: sim.add_force_operator("late", lambda t, dt, p: None),
                    lambda: sim.write_checkpoint(path)]
        refused = []

        def meddles(time, dt, particles):
            for attempt in attempts:
                with self.assertRaisesRegex(polydem.Error, "inside force operator 'meddles'"):
                    attempt()
                refused.append(attempt)
            return None

        sim.add_force_operator("meddles", meddles)  # called at once: the leapfrog's start
        sim.step(3)
        self.assertEqual(len(refused), 4 * len(attempts))
        self.assertEqual(sim.step_count, 3)
        self.assertEqual(sim.force_operators, ["meddles"])
        self.assertFalse(os.path.exists(path))
        plain = polydem.Simulation(SCENE)
        plain.step(3)
        self.assertEqual(sim.state_hash(), plain.state_hash())

    def test_a_stepping_operator_ends_the_step(self):
        sim = polydem.Simulation(SCENE)
        sim.step()
        sim.add_force_operator("steps", lambda t, dt, p: sim.step())
        with self.assertRaisesRegex(polydem.Error,
                                    "Simulation.step called from inside force operator 'steps'"):
            sim.step()

    def test_forces_out_of_reach_are_refused(self):
        # A force is refused if it is not finite or would alone move its particle more than
        # step_reach in one step (|F| dt^2 / m); one just within that is taken.
        limit = 1 - 1e-9
        for factor, error in ((limit, None), (1 / limit, "would move it"),
                              (float("inf"), "is not finite"), (float("nan"), "is not finite")):
            sim = polydem.Simulation(SCENE)
            sim.step()
            reach, dt = sim.step_reach, sim.dt

            def push(time, step, particles):
                forces = np.zeros((len(particles["uid"]), 3))
                forces[:, 0] = factor * reach * particles["mass"] / (dt * dt)
                return forces

            sim.add_force_operator("push", push)
            if error is None:
                sim.step()
                self.assertEqual(sim.step_count, 2)
            else:
                with self.assertRaisesRegex(ValueError, "force operator 'push' returned the "
                                            "force .* for particle 1, which " + error):
                    sim.step()


class SceneOperator(unittest.TestCase):
    """An [[operator]] without a library, named in the scene and supplied from Python."""

    def scene_file(self, name, operators):
        with open(SCENE) as f:
            text = f.read()
        work = os.environ["POLYDEM_TEST_WORK"]
        os.makedirs(work, exist_ok=True)
        path = os.path.join(work, name)
        with open(path, "w") as f:
            f.write(text + "\n" + operators)
        return path, text.count("\n") + 2  # the line of the [[operator]] header

    @staticmethod
    def uplift(time, dt, particles):
        forces = np.zeros((len(particles["uid"]), 3))
        forces[:, 2] = 0.5 * G * particles["mass"]
        return forces

    def test_named_operator_runs_at_its_place(self):
        path, _ = self.scene_file("scene_operator.toml", '[[operator]]\nname = "uplift"\n')
        sim = polydem.Simulation(path, operators={"uplift": self.uplift})
        self.assertEqual(sim.force_operators, ["uplift"])
        sim.run()
        t = sim.time
        z = sim.particles()["position"][0, 2]
        expected = 0.5 * (0.5 * G) * t * t
        self.assertAlmostEqual(5.0 - z, expected, delta=1e-9 * expected)
        # The same bits as the operator added in code before the first step.
        added = polydem.Simulation(SCENE)
        added.add_force_operator("uplift", self.uplift)
        added.run()
        self.assertEqual(sim.state_hash(), added.state_hash())

    def test_misnamed_operators_are_reported(self):
        path, line = self.scene_file("scene_operator_missing.toml",
                                     '[[operator]]\nname = "uplift"\n')
        with self.assertRaisesRegex(polydem.InputError,
                                    f"{path}:{line}.*'uplift' names no library"):
            polydem.Simulation(path)
        with self.assertRaisesRegex(polydem.Error, "names no \\[\\[operator\\]\\] 'drag'"):
            polydem.Simulation(path, operators={"uplift": self.uplift, "drag": self.uplift})
        with self.assertRaises(TypeError):
            polydem.Simulation(path, operators={"uplift": 3})
        taken, line = self.scene_file("scene_operator_taken.toml",
                                      '[[operator]]\nname = "contacts"\n')
        with self.assertRaisesRegex(polydem.InputError,
                                    f"{taken}:{line}.*name of an operator of the step"):
            polydem.Simulation(taken, operators={"contacts": self.uplift})


if __name__ == "__main__":
    unittest.main()

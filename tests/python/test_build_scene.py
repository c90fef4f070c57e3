"""Scenes built entirely in Python (polydem.Scene), without a scene file:
physics against analytical answers, checkpoint and restart with the bits of an uninterrupted run,
the same run as `polydem run` of the scene written as TOML, and bad arguments that raise.

Runs on one rank (python_build_scene) and on two through mpiexec (python_build_scene_np2), where
the checkpoint of the two-rank run is also continued on each rank alone (an mpi4py COMM_SELF).
"""
import json
import math
import os
import subprocess
import tempfile
import tomllib
import unittest

import numpy as np

import polydem

polydem.set_log_level("warning")
RANK, SIZE = polydem.mpi_rank(), polydem.mpi_size()
G = 9.81


def work_dir(name):
    """A directory all ranks share (rank 0 makes it; the name does not depend on the rank)."""
    root = os.environ.get("POLYDEM_TEST_WORK") or tempfile.gettempdir()
    path = os.path.join(root, "build_scene_np%d" % SIZE, name)
    if RANK == 0:
        os.makedirs(path, exist_ok=True)
    from mpi4py import MPI
    MPI.COMM_WORLD.Barrier()
    return path


def falling_cubes(dt=1e-3, steps=40):
    """Three cubes dropped in vacuum, far apart: nothing but gravity acts on them."""
    s = polydem.Scene("falling-cubes", title="Three cubes in free fall", dt=dt, steps=steps,
                      gravity=(0, 0, -G))
    s.add_material("rock", density=2650, kn=1e6, ks=5e5, friction_angle=30)
    s.add_shape("cube", box=(1, 1, 1))
    s.add_shape("tet", type="tetrahedron", edge=1.5)
    uids = [s.add_particle("cube", "rock", position=(4.0 * i, 0, 10), label="c%d" % i)
            for i in range(2)]
    uids.append(s.add_particle("tet", "rock", position=(0, 6, 10), velocity=(1, 0, 0),
                               orientation=(math.cos(0.3), 0, 0, math.sin(0.3))))
    return s, uids


def sliding_block(tilt_deg=30.0, friction_deg=20.0, steps=3000):
    """A block on a fixed slab under gravity tilted by `tilt_deg`: the plane of Coulomb's sliding
    block, with the slab horizontal so that the contact does not move across blocks."""
    t = math.radians(tilt_deg)
    s = polydem.Scene("sliding-block", dt=2e-5, steps=steps,
                      gravity=(G * math.sin(t), 0, -G * math.cos(t)))
    s.add_material("rock", density=2650, kn=2e9, ks=1e9, friction_angle=friction_deg,
                   normal_damping=0.3)
    s.add_shape("block", box=(1, 1, 0.5))
    s.add_shape("slab", type="box", min=(-3, -2, -1), max=(6, 2, 0))
    s.add_particle("slab", "rock", fixed=True, label="slab")
    m = 2650 * 0.5
    sink = m * G * math.cos(t) / 2e9  # the static overlap of the sub-contact springs
    block = s.add_particle("block", "rock", position=(0, 0, 0.25 - sink), label="block")
    return s, block


class Physics(unittest.TestCase):
    def test_free_fall_is_exact(self):
        dt, n = 1e-3, 40
        s, uids = falling_cubes(dt, n)
        sim = polydem.Simulation(s)
        sim.run()
        p = sim.particles(gather=True)
        self.assertEqual(list(p["uid"]), uids)
        self.assertEqual(p["label"], ["c0", "c1", ""])
        # The leapfrog with the half-step start (velocities at t - dt/2) integrates constant
        # acceleration exactly: z = z0 - g t^2 / 2, x = x0 + vx t.
        t = n * dt
        self.assertAlmostEqual(sim.time, t, places=12)
        np.testing.assert_allclose(p["position"][:, 2], 10 - 0.5 * G * t * t, rtol=1e-12)
        self.assertAlmostEqual(p["position"][2, 0], 1.0 * t, places=12)
        np.testing.assert_allclose(p["velocity"][:, 2], -G * (t - dt / 2), rtol=1e-12)
        self.assertEqual(len(sim.contacts()["uids"]), 0)

    def test_coulomb_sliding_acceleration(self):
        tilt, phi = 30.0, 20.0
        s, block = sliding_block(tilt, phi, steps=4000)
        sim = polydem.Simulation(s)
        sim.step(2000)  # let the contact settle
        v1, t1 = self._velocity(sim, block), sim.time
        sim.step(2000)
        v2, t2 = self._velocity(sim, block), sim.time
        a = (v2[0] - v1[0]) / (t2 - t1)
        t, f = math.radians(tilt), math.radians(phi)
        expected = G * (math.sin(t) - math.tan(f) * math.cos(t))  # rigid block, Coulomb friction
        if RANK == 0:
            print("sliding block: a = %.4f m/s^2, rigid-block Coulomb law %.4f" % (a, expected))
        self.assertLess(abs(a - expected), 0.02 * expected)
        contacts = sim.contacts()
        if len(contacts["uids"]):  # on the rank that owns the block
            self.assertTrue(np.all(contacts["uids"] == [1, block]))

    @staticmethod
    def _velocity(sim, uid):
        p = sim.particles(gather=True)
        return p["velocity"][list(p["uid"]).index(uid)]


class CheckpointRestart(unittest.TestCase):
    def test_restart_continues_the_uninterrupted_run(self):
        s, _ = sliding_block(steps=600)
        whole = polydem.Simulation(s)
        whole.step(600)
        expected = whole.state_hash()

        path = os.path.join(work_dir("restart"), "sliding.h5")
        first = polydem.Simulation(s)
        first.step(250)
        first.write_checkpoint(path)
        del first
        again = polydem.Simulation.restart(path)
        self.assertEqual(again.step_count, 250)
        self.assertEqual(again.scene.text, s.to_toml())  # the scene came back from the file
        again.step(350)
        self.assertEqual(again.state_hash(), expected)

        # On another rank count: each rank continues the file alone (mpi4py COMM_SELF).
        from mpi4py import MPI
        alone = polydem.Simulation.restart(path, comm=MPI.COMM_SELF)
        alone.step(350)
        self.assertEqual(alone.state_hash(), expected)

    def test_polydem_run_continues_a_python_checkpoint(self):
        exe = os.environ.get("POLYDEM_EXECUTABLE")
        if SIZE > 1 or not exe:
            return  # the command line is run from the one-rank test
        s, _ = sliding_block(steps=600)
        sim = polydem.Simulation(s)
        sim.step(250)
        d = work_dir("cli_restart")
        path = os.path.join(d, "half.h5")
        sim.write_checkpoint(path)
        sim.run()
        out = os.path.join(d, "out")
        subprocess.run([exe, "run", "--restart", path, "--out", out, "--no-snapshots",
                        "--quiet"], check=True)
        with open(os.path.join(out, "summary.json")) as f:
            self.assertEqual(json.load(f)["state_hash"], sim.state_hash())

    def test_a_restarted_run_checkpoints_again(self):
        s, _ = falling_cubes(steps=30)
        whole = polydem.Simulation(s)
        whole.step(30)
        d = work_dir("twice")
        a = polydem.Simulation(s)
        a.step(10)
        a.write_checkpoint(os.path.join(d, "a.h5"))
        b = polydem.Simulation.restart(os.path.join(d, "a.h5"))
        b.step(10)
        b.write_checkpoint(os.path.join(d, "b.h5"))
        c = polydem.Simulation.restart(os.path.join(d, "b.h5"))
        c.step(10)
        self.assertEqual(c.state_hash(), whole.state_hash())


class SameRunAsTheFile(unittest.TestCase):
    def test_explicit_world_communicator_is_the_default(self):
        from mpi4py import MPI
        s, _ = falling_cubes(steps=10)
        a = polydem.Simulation(s)
        a.run()
        b = polydem.Simulation(s, comm=MPI.COMM_WORLD)
        b.run()
        self.assertEqual(a.state_hash(), b.state_hash())

    def test_polydem_run_of_the_saved_scene_has_the_same_hash(self):
        s, _ = sliding_block(steps=300)
        s.set_output(monitor=["block"], series_every=50)
        s.add_check("slides", "displacement", particle="block", direction=(1, 0, 0),
                    compare="report", reference="recorded only")
        text = s.to_toml()
        doc = tomllib.loads(text)  # valid TOML, holding what was set
        self.assertEqual(doc["simulation"]["dt"], 2e-5)
        self.assertEqual([p.get("label") for p in doc["particle"]], ["slab", "block"])
        result = polydem.run(s)
        from_python = result["state_hash"]
        self.assertEqual([c["name"] for c in result["checks"]], ["slides"])
        self.assertGreater(result["checks"][0]["value"], 0.0)  # down the slope
        sim = polydem.Simulation(s)
        sim.run()
        self.assertEqual(sim.state_hash(), from_python)
        exe = os.environ.get("POLYDEM_EXECUTABLE")
        if SIZE > 1 or not exe:
            return  # the command line is run from the one-rank test
        d = work_dir("cli")
        path = s.save(os.path.join(d, "sliding.toml"))
        out = os.path.join(d, "out")
        subprocess.run([exe, "run", path, "--out", out, "--no-snapshots", "--quiet"], check=True)
        with open(os.path.join(out, "summary.json")) as f:
            self.assertEqual(json.load(f)["state_hash"], from_python)

    def test_grid_and_rock_mass(self):
        s = polydem.Scene("grid-and-rock", dt=2e-5, steps=5)
        s.add_material("rock", density=2650, kn=1e9, ks=5e8, friction_angle=35)
        s.add_material("bedrock", density=2650, kn=1e9, ks=5e8, friction_angle=35)
        s.add_shape("pebble", type="octahedron", edge=0.4)
        grid = s.add_particle_grid("pebble", "rock", count=(3, 2, 2), spacing=0.8,
                                   origin=(0, 0, 12), label_prefix="g")
        self.assertEqual(list(grid), list(range(1, 13)))
        blocks = s.add_rock_mass(
            "slope", "rock", fixed_material="bedrock",
            region={"type": "box", "min": (-2, -2, 0), "max": (6, 3, 4)},
            planes=[{"name": "base", "dip": 0, "dip_direction": 90, "point": (0, 0, 1),
                     "fixed": "below"}],
            joint_sets=[{"name": "J1", "dip": 70, "dip_direction": 90, "spacing": 2.5}],
            label_prefix="b")
        cut = polydem.cut_rock_mass(
            {"type": "box", "min": (-2, -2, 0), "max": (6, 3, 4)},
            joint_sets=[{"name": "J1", "dip": 70, "dip_direction": 90, "spacing": 2.5}],
            planes=[{"name": "base", "dip": 0, "dip_direction": 90, "point": (0, 0, 1),
                     "fixed": "below"}])
        self.assertEqual(len(blocks), len(cut["volume"]))
        self.assertEqual(blocks.start, 13)
        last = s.add_particle("pebble", "rock", position=(0, 0, 20), label="last")
        self.assertEqual(last, blocks.stop)
        built = s.build()
        self.assertEqual(built.num_particles, last)
        self.assertEqual(built.rock_masses[0]["first_uid"], 13)
        labels = built.particles["label"]
        self.assertEqual(labels[0], "g_0_0_0")
        self.assertEqual(labels[-1], "last")
        sim = polydem.Simulation(s)
        sim.run()
        self.assertEqual(sim.step_count, 5)

    def test_driver_and_settings(self):
        dt, n = 1e-3, 8
        s = polydem.Scene("driven", dt=dt, steps=n, gravity=(0, 0, 0))
        s.add_material("steel", density=7800, kn=1e6)
        s.add_shape("plate", box=(2, 2, 0.1))
        s.add_driver("lift", velocity=(0, 0, 0.25), start_time=0)
        plate = s.add_particle("plate", "steel", position=(0, 0, 1), driver="lift", label="plate")
        s.set_domain(min=(-5, -5, -5), max=(5, 5, 5), balancer="sfc")
        s.set_output(monitor=["plate"], series_every=2)
        s.set_checkpoint(every_steps=100, keep=1)
        s.set_equilibrium(enabled=False, force_ratio=1e-4)
        s.set_kernel_params(lp_rounding=0.1)
        s.set_simulation(kernel="lp", contact_model="point")
        built = s.build()
        self.assertEqual((built.kernel, built.contact_model), ("lp", "point"))
        self.assertEqual(built.monitor, ["plate"])
        self.assertFalse(built.equilibrium)
        self.assertEqual(built.drivers[0]["velocity"].tolist(), [0, 0, 0.25])
        sim = polydem.Simulation(s)
        sim.run()
        p = sim.particles(gather=True)
        self.assertEqual(int(p["flags"][0]) & polydem.FLAG_DRIVEN, polydem.FLAG_DRIVEN)
        self.assertEqual(int(p["uid"][0]), plate)
        self.assertAlmostEqual(p["position"][0, 2], 1 + 0.25 * n * dt, places=12)

    def test_changing_values_rebuilds_the_scene(self):
        s, uids = falling_cubes(steps=10)
        s.set_particle(uids[0], velocity=(0, 0, 5))
        s.set_material("rock", friction_angle=10)
        s.gravity = (0, 0, -1.0)
        s.dt = 5e-4
        self.assertEqual(s.dt, 5e-4)
        built = s.build()
        self.assertEqual(built.dt, 5e-4)
        self.assertEqual(built.particles["velocity"][0].tolist(), [0, 0, 5])
        self.assertEqual(built.materials[0]["friction_angle"], 10)
        self.assertEqual(built.gravity.tolist(), [0, 0, -1.0])
        self.assertEqual(built.particles["label"][0], "c0")


class ChangeBetweenSteps(unittest.TestCase):
    def run_with_kick(self, comm=None, checkpoint=None):
        """Two cubes pressed together by gravity tilted sideways; after 200 steps the upper one
        is kicked sideways and set spinning, then 200 steps more."""
        s = polydem.Scene("kick", dt=2e-5, steps=400, gravity=(0, 0, -G))
        s.add_material("rock", density=2650, kn=2e9, ks=1e9, friction_angle=30,
                       normal_damping=0.3)
        s.add_shape("cube", box=(1, 1, 1))
        s.add_particle("cube", "rock", position=(0, 0, 0.5), fixed=True)
        top = s.add_particle("cube", "rock", position=(0, 0, 1.5 - 2650 * G / 2e9))
        free = s.add_particle("cube", "rock", position=(5, 0, 10))
        sim = polydem.Simulation(s, comm=comm)
        sim.step(200)
        sim.set_velocity(top, velocity=(0.5, 0, 0))
        sim.set_velocity(free, angular_velocity=(0, 0, 2.0))
        if checkpoint:
            sim.write_checkpoint(checkpoint)
        sim.step(200)
        return sim, top, free

    def test_kick_is_deterministic_and_survives_a_restart(self):
        from mpi4py import MPI
        sim, top, free = self.run_with_kick()
        p = sim.particles(gather=True)
        i = list(p["uid"]).index(free)
        # A cube spins freely about a principal axis: w stays as set, to rounding.
        np.testing.assert_allclose(p["angular_velocity"][i], [0, 0, 2.0], atol=1e-12)
        j = list(p["uid"]).index(top)
        self.assertGreater(p["position"][j, 0], 0.0)  # it moved the way it was kicked
        self.assertLess(p["velocity"][j, 0], 0.5)      # and friction slows it
        path = os.path.join(work_dir("kick"), "kick.h5")
        with_checkpoint, _, _ = self.run_with_kick(checkpoint=path)
        self.assertEqual(with_checkpoint.state_hash(), sim.state_hash())
        restarted = polydem.Simulation.restart(path)
        restarted.step(200)
        self.assertEqual(restarted.state_hash(), sim.state_hash())
        alone, _, _ = self.run_with_kick(comm=MPI.COMM_SELF)  # one rank, beside the others
        self.assertEqual(alone.state_hash(), sim.state_hash())

    def test_bad_kicks(self):
        s, uids = falling_cubes(steps=5)
        s.add_particle("cube", "rock", position=(0, 20, 0), fixed=True)
        sim = polydem.Simulation(s)
        with self.assertRaisesRegex(ValueError, "no free particle has uid 4"):
            sim.set_velocity(4, velocity=(1, 0, 0))
        with self.assertRaisesRegex(ValueError, "no free particle has uid 99"):
            sim.set_velocity(99, velocity=(1, 0, 0))
        with self.assertRaisesRegex(ValueError, "velocity must be finite"):
            sim.set_velocity(uids[0], velocity=(float("nan"), 0, 0))
        with self.assertRaisesRegex(ValueError, "angular_velocity must be a 3-vector"):
            sim.set_velocity(uids[0], angular_velocity=(1, 0))

    def test_kicks_beyond_the_step_reach(self):
        # Finite but absurd: a value that would move a point of the particle more than
        # step_reach in one step (|v| dt, |w| r dt) is refused on every rank and changes
        # nothing; one just within it is taken.
        s, uids = falling_cubes(steps=5)
        sim = polydem.Simulation(s)
        reach, dt = sim.step_reach, sim.dt
        before = sim.particles(gather=True)
        r = sim.shapes[before["shape"][0]].circumradius
        for kick, text in ((dict(velocity=(1e308, 0, 0)), "the velocity"),
                           (dict(velocity=(0, 0, -1.001 * reach / dt)), "the velocity"),
                           (dict(velocity=(0, 0, 1), angular_velocity=(0, 1.001 * reach / (r * dt), 0)),
                            "the angular velocity")):
            with self.assertRaisesRegex(ValueError, "set_velocity: particle %d: %s .* would move "
                                        "it .* more than" % (uids[0], text)):
                sim.set_velocity(uids[0], **kick)
            after = sim.particles(gather=True)
            for key in ("velocity", "angular_velocity"):
                np.testing.assert_array_equal(after[key], before[key])
        sim.set_velocity(uids[0], velocity=(0, 0, -0.999 * reach / dt),
                         angular_velocity=(0, 0.999 * reach / (r * dt), 0))
        p = sim.particles(gather=True)
        self.assertEqual(p["velocity"][0, 2], -0.999 * reach / dt)


class BadArguments(unittest.TestCase):
    def setUp(self):
        self.s, _ = falling_cubes()

    def assertRaisesWith(self, kind, text, f, *args, **kwargs):
        with self.assertRaises(kind) as c:
            f(*args, **kwargs)
        self.assertIn(text, str(c.exception))

    def test_messages(self):
        s = self.s
        self.assertRaisesWith(ValueError, "unknown material 'granite'", s.add_particle, "cube",
                              "granite")
        self.assertRaisesWith(ValueError, "unknown shape 'sphere'", s.add_particle, "sphere",
                              "rock")
        self.assertRaisesWith(ValueError, "position must have shape (3,), got shape (2,)",
                              s.add_particle, "cube", "rock", position=(1, 2))
        self.assertRaisesWith(ValueError, "density must be > 0.0, got -1.0", s.add_material,
                              "soft", density=-1.0, kn=1e6)
        self.assertRaisesWith(ValueError, "density must be finite, got nan", s.add_material,
                              "soft", density=float("nan"), kn=1e6)
        self.assertRaisesWith(ValueError, "velocity must be finite", s.add_particle, "cube",
                              "rock", velocity=(0, float("inf"), 0))
        self.assertRaisesWith(ValueError, "a material named 'rock' already exists",
                              s.add_material, "rock", density=1000, kn=1)
        self.assertRaisesWith(ValueError, "the label 'c0' is already used", s.add_particle,
                              "cube", "rock", label="c0")
        self.assertRaisesWith(ValueError, "vertices must have shape (n, 3)", s.add_shape, "flat",
                              vertices=np.zeros((4, 2)))
        self.assertRaisesWith(ValueError, "add_shape('flat')", s.add_shape, "flat",
                              vertices=[(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0)])
        self.assertRaisesWith(TypeError, "density must be a number", s.add_material, "x",
                              density=None, kn=1)
        self.assertRaisesWith(TypeError, "unknown key 'dtt'", s.set_simulation, dtt=1e-3)
        self.assertRaisesWith(ValueError, "Scene dt must be > 0.0", s.set_simulation, dt=0)
        self.assertRaisesWith(TypeError, "comm must be None", polydem.Simulation, s, comm="world")
        self.assertRaisesWith(polydem.InputError, "'magic' is not one of", polydem.Simulation,
                              polydem.Scene("k", dt=1e-3, steps=1, kernel="magic"))
        self.assertRaisesWith(polydem.CheckpointError, "no-such.h5",
                              polydem.Simulation.restart, os.path.join(work_dir("bad"),
                                                                       "no-such.h5"))
        s.add_check("wrong", "no-such-kind")  # judged when built, and taken back
        self.assertRaisesWith(polydem.InputError, "'no-such-kind' is not a check kind", s.build)
        s.remove_check("wrong")
        sim = polydem.Simulation(s)
        self.assertRaisesWith(TypeError, "path must be a str", sim.write_checkpoint, 42)
        # The scene still builds: every refused call left it as it was.
        self.assertEqual(s.build().num_particles, 3)

    def test_a_refused_setting_changes_nothing(self):
        # The good keys before and after the bad one are not taken either: all or nothing.
        s = self.s
        before = s.to_toml()
        for bad in (dict(kernel="lp", dt=-1.0, steps=7), dict(steps=7, gravity=(0, 0)),
                    dict(end_time=2.0, dtt=1e-3), dict(dt=None, contact_margin=-1.0)):
            with self.assertRaises((TypeError, ValueError)):
                s.set_simulation(**bad)
            self.assertEqual(s.to_toml(), before)
        with self.assertRaises(ValueError):
            s.steps = 0
        self.assertEqual(s.to_toml(), before)
        s.set_simulation(kernel="lp", steps=7)
        self.assertEqual((s.kernel, s.steps), ("lp", 7))

    def test_the_interpreter_survives_bad_calls(self):
        if SIZE > 1:
            return  # one child interpreter per rank would be an MPI job of its own
        code = ("import polydem\n"
                "s = polydem.Scene('x', dt=1e-3, steps=1)\n"
                "for f in (lambda: s.add_material('m', density=float('nan'), kn=1),\n"
                "          lambda: polydem.Simulation(s, comm=3.5),\n"
                "          lambda: polydem.Simulation.restart(None),\n"
                "          lambda: polydem.Simulation(s)):\n"
                "    try:\n        f()\n    except (TypeError, ValueError, polydem.Error) as e:\n"
                "        print(type(e).__name__)\n"
                "print('alive')\n")
        out = subprocess.run([os.sys.executable, "-c", code], capture_output=True, text=True,
                             timeout=60)
        self.assertEqual(out.returncode, 0, out.stderr)
        self.assertEqual(out.stdout.split(), ["ValueError", "TypeError", "TypeError",
                                              "InputError", "alive"])


if __name__ == "__main__":
    unittest.main()

"""Misuse of the Python API raises an exception instead of crashing or hanging the interpreter:
every property getter of every class called on None (Simulation.time.fget,
ConvexPolyhedron.volume.fget, ...), unbound methods called with None, and a run of a scene whose
stop conditions were cleared from Python. Each case runs in a child interpreter, so that a
segfault or an endless loop is a failure of that case, not of the whole test.
"""
import os
import subprocess
import sys
import unittest

SCENE = os.path.join(os.environ["POLYDEM_SOURCE_DIR"], "benchmark_scenes", "S-BLOCK-ON-PLANE.toml")


def child(code, timeout=60):
    """Runs `code` in a new interpreter with polydem imported; (exit status, output)."""
    out = subprocess.run([sys.executable, "-c", "import polydem\n" + code], capture_output=True,
                         text=True, timeout=timeout)
    return out.returncode, out.stdout + out.stderr


def classes():
    code = ("import inspect\n"
            "for n, c in vars(polydem).items():\n"
            "    if inspect.isclass(c) and type(c).__name__ == 'pybind11_type':\n"
            "        print(n)\n")
    status, out = child(code)
    assert status == 0, out
    return out.split()


class NoneAsSelf(unittest.TestCase):
    def test_every_property_getter_raises_type_error(self):
        names = classes()
        self.assertIn("Simulation", names)
        self.assertIn("ConvexPolyhedron", names)
        for name in names:
            code = ("failures = []\n"
                    "for attr, value in vars(polydem.%s).items():\n"
                    "    if isinstance(value, property):\n"
                    "        try:\n"
                    "            value.fget(None)\n"
                    "            failures.append(attr + ': no exception')\n"
                    "        except TypeError:\n"
                    "            pass\n"
                    "print(failures)\n"
                    "raise SystemExit(1 if failures else 0)\n" % name)
            status, out = child(code)
            self.assertEqual(status, 0, "%s: %s" % (name, out))

    def test_unbound_methods_with_none_raise_type_error(self):
        for call in ("polydem.ConvexPolyhedron.scaled(None, 2.0)",
                     "polydem.Simulation.run_equilibrium(None)",
                     "polydem.Simulation.run(None)", "polydem.Simulation.step(None, 1)"):
            status, out = child("try:\n    %s\nexcept TypeError:\n    raise SystemExit(0)\n"
                                "raise SystemExit(1)\n" % call)
            self.assertEqual(status, 0, "%s: %s" % (call, out))


class NoStopCondition(unittest.TestCase):
    def test_run_without_end_time_or_steps_raises(self):
        code = ("scene = polydem.read_scene(%r)\n"
                "scene.end_time = None\nscene.steps = None\n"
                "try:\n    polydem.run(scene)\nexcept polydem.Error as e:\n"
                "    print(e)\n    raise SystemExit(0)\n"
                "raise SystemExit(1)\n" % SCENE)
        try:
            status, out = child(code, timeout=60)
        except subprocess.TimeoutExpired:
            self.fail("polydem.run of a scene without a stop condition did not return in 60 s")
        self.assertEqual(status, 0, out)
        self.assertIn("neither end_time nor steps", out)

    def test_simulation_run_without_end_time_or_steps_raises(self):
        code = ("scene = polydem.read_scene(%r)\n"
                "scene.end_time = None\nscene.steps = None\n"
                "sim = polydem.Simulation(scene)\n"
                "try:\n    sim.run()\nexcept (ValueError, polydem.Error):\n"
                "    raise SystemExit(0)\n"
                "raise SystemExit(1)\n" % SCENE)
        status, out = child(code)
        self.assertEqual(status, 0, out)


if __name__ == "__main__":
    unittest.main()

"""polydem: polyhedral discrete element method for rock-slope failure and runout, from Python.

Build shapes and inspect them, resolve contacts with any kernel, build scenes in Python or read
scene files, run and step them, read their state as numpy arrays, write checkpoints and restart.
SI units throughout; arrays of points are (n, 3).

    import polydem
    cube = polydem.ConvexPolyhedron(polydem.shapes.cube(1.0))
    result = polydem.run("benchmark_scenes/S-BLOCK-ON-PLANE.toml", end_time=0.05)
    s = polydem.Scene("drop", dt=1e-4, end_time=0.5)
    s.add_material("rock", density=2650, kn=1e8, ks=5e7, friction_angle=30)
    s.add_shape("cube", box=(1, 1, 1))
    s.add_particle("cube", "rock", position=(0, 0, 2))
    sim = polydem.Simulation(s)          # or a scene file's path, on comm=an mpi4py communicator
    sim.step(100)
    state = sim.particles()
    sim.write_checkpoint("drop.h5")
    sim = polydem.Simulation.restart("drop.h5")

Importing polydem initialises MPI (unless mpi4py or another library did) and finalises it when
the interpreter exits, so a plain script runs on one rank and `mpirun -n 4 python3 script.py`
runs one Simulation over all four. See docs/python.md.
"""
import importlib as _importlib
import os as _os
import sys as _sys

from . import _polydem
from ._polydem import (
    FLAG_DRIVEN,
    FLAG_FIXED,
    FLAG_GHOST,
    CheckpointError,
    ConvexPolyhedron,
    Error,
    GeometryError,
    InputError,
    SceneData,
    Simulation,
    SimulationError,
    collide,
    contact_cases,
    cut_rock_mass,
    kernels,
    log_level,
    mpi_abort,
    mpi_rank,
    mpi_size,
    set_log_level,
)
from . import shapes
from .scene_builder import Scene

__version__ = _polydem.__version__

__all__ = [
    "CheckpointError", "ConvexPolyhedron", "Error", "FLAG_DRIVEN", "FLAG_FIXED", "FLAG_GHOST",
    "GeometryError", "InputError", "Scene", "SceneData", "Simulation", "SimulationError", "collide",
    "contact_cases", "cut_rock_mass", "kernels", "log_level", "mpi_abort", "mpi_rank", "mpi_size", "parse_scene",
    "read_scene", "run", "set_log_level", "shapes",
]


def read_scene(path):
    """Reads and checks the scene file at `path` (str or os.PathLike) and returns a Scene.

    Raises polydem.InputError (a ValueError) whose message starts with 'file:line: ' and whose
    attributes `file` and `line` name the first problem.
    """
    return _polydem.read_scene(_os.fspath(path))


def parse_scene(text, name="<string>"):
    """Reads a scene from TOML text; `name` is the file name that messages carry."""
    return _polydem.parse_scene(text, name)


def run(scene, out=None, steps=None, end_time=None, kernel=None, snapshots=True,
        progress_every=0, comm=None):
    """Runs a scene as `polydem run` does and returns its results (collective on all ranks).

    `scene` is a polydem.Scene, a SceneData or the path of a scene file. `out` is the output
    directory (summary.json, series.csv, ParaView snapshots unless snapshots=False, checkpoints
    of the scene's [checkpoint] table); None writes no files. `steps` or `end_time` replace the
    scene's stop condition, `kernel` its contact kernel; `progress_every` prints a progress line
    every so many steps (0: the scene's, or every 5 s). `comm`: None (MPI_COMM_WORLD) or an
    mpi4py communicator.

    Returns a dict: checks (list of dicts name, kind, value, expected, tolerance, compare, pass,
    reference, note), all_checks_pass, state_hash (as in summary.json), steps, time [s],
    equilibrium_steps, wall_seconds.
    """
    if isinstance(scene, Scene):
        scene = scene.build()
    elif not isinstance(scene, SceneData):
        scene = read_scene(scene)
    return _polydem.run_scene(scene, "" if out is None else _os.fspath(out), steps, end_time,
                              kernel, snapshots, progress_every, comm)


def __getattr__(name):
    # polydem.plots imports matplotlib: loaded on first use, not with the package. Through
    # importlib, since `from . import plots` would look the attribute up here again (recursion).
    if name == "plots":
        return _importlib.import_module(__name__ + ".plots")
    raise AttributeError("module 'polydem' has no attribute %r" % name)


def _abort_on_uncaught_exception(kind, value, traceback):
    # On several ranks, an exception on one rank leaves the others waiting forever in the next
    # collective call: print it, then end the whole job.
    _sys.__excepthook__(kind, value, traceback)
    _sys.stderr.flush()
    mpi_abort(1)


if mpi_size() > 1 and _sys.excepthook is _sys.__excepthook__:
    _sys.excepthook = _abort_on_uncaught_exception

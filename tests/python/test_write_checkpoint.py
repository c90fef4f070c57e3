"""Files polydem did not write are never touched, from Python (docs/python.md, docs/checkpoint.md):
Simulation.write_checkpoint(path) writes only to a new path, over an empty file or over a polydem
checkpoint, and refuses a FIFO, a device, a directory, an unrelated file or a link to one with
polydem.CheckpointError naming the path, leaving it as it was; polydem.run refuses an output
folder that another run holds.

Runs on one rank (python_write_checkpoint) and on two through mpiexec (..._np2): every rank gets
the same error.
"""
import os
import shutil
import socket
import stat
import tempfile
import unittest

import polydem

polydem.set_log_level("warning")
RANK, SIZE = polydem.mpi_rank(), polydem.mpi_size()


def barrier():
    from mpi4py import MPI
    MPI.COMM_WORLD.Barrier()


def work_dir(name):
    """An empty directory all ranks share (rank 0 makes it)."""
    root = os.environ.get("POLYDEM_TEST_WORK") or tempfile.gettempdir()
    path = os.path.join(root, "write_checkpoint_np%d" % SIZE, name)
    if RANK == 0:
        shutil.rmtree(path, ignore_errors=True)
        os.makedirs(path)
    barrier()
    return path


def on_rank_zero(make):
    if RANK == 0:
        make()
    barrier()


def two_cubes():
    s = polydem.Scene("two-cubes", dt=1e-3, steps=10, gravity=(0, 0, -9.81))
    s.add_material("rock", density=2650, kn=1e6, ks=5e5, friction_angle=30)
    s.add_shape("cube", box=(1, 1, 1))
    s.add_particle("cube", "rock", position=(0, 0, 5))
    s.add_particle("cube", "rock", position=(3, 0, 5))
    return s


class WriteCheckpointTarget(unittest.TestCase):
    def setUp(self):
        self.sim = polydem.Simulation(two_cubes())
        self.sim.step(3)

    def refused(self, path, *parts):
        """write_checkpoint(path) raises CheckpointError naming the path and `parts`; no
        temporary file is left next to it."""
        folder = os.path.dirname(os.path.abspath(path))
        before = sorted(os.listdir(folder))
        with self.assertRaises(polydem.CheckpointError) as raised:
            self.sim.write_checkpoint(path)
        message = str(raised.exception)
        self.assertIn("checkpoint %s: " % path, message)
        for part in parts:
            self.assertIn(part, message)
        barrier()
        self.assertEqual(sorted(os.listdir(folder)), before)

    def test_fifo_is_refused_and_stays_a_fifo(self):
        fifo = os.path.join(work_dir("fifo"), "pipe.h5")
        on_rank_zero(lambda: os.mkfifo(fifo))
        self.refused(fifo, "is a FIFO (named pipe), not a file")
        self.assertTrue(stat.S_ISFIFO(os.stat(fifo).st_mode))

    def test_dev_null_is_refused_and_left_alone(self):
        before = os.stat("/dev/null")
        self.refused("/dev/null", "is a device, not a file")
        link = os.path.join(work_dir("null"), "null.h5")
        on_rank_zero(lambda: os.symlink("/dev/null", link))
        self.refused(link, "is a symbolic link to /dev/null, which is a device")
        after = os.stat("/dev/null")
        self.assertTrue(stat.S_ISCHR(after.st_mode))
        self.assertEqual((after.st_ino, after.st_rdev), (before.st_ino, before.st_rdev))
        self.assertTrue(os.path.islink(link))

    def test_unrelated_file_and_directory_are_refused(self):
        d = work_dir("unrelated")
        notes = os.path.join(d, "notes.h5")
        text = "field notes of the slope, not a checkpoint\n"

        def make():
            with open(notes, "w") as f:
                f.write(text)
            os.mkdir(os.path.join(d, "folder.h5"))
        on_rank_zero(make)
        self.refused(notes, "exists and is not a polydem checkpoint (%d bytes)" % len(text),
                     "remove the file or choose another path")
        with open(notes) as f:
            self.assertEqual(f.read(), text)
        self.refused(os.path.join(d, "folder.h5"), "is a directory")

    def test_empty_file_and_own_checkpoint_are_replaced(self):
        d = work_dir("replace")
        path = os.path.join(d, "run.h5")
        on_rank_zero(lambda: open(path, "w").close())  # as tempfile.mkstemp() leaves one
        self.sim.write_checkpoint(path)
        self.sim.step(2)
        self.sim.write_checkpoint(path)  # over its own checkpoint
        barrier()
        self.assertEqual(os.listdir(d), ["run.h5"])
        again = polydem.Simulation.restart(path)
        self.assertEqual(again.step_count, 5)
        self.assertEqual(again.state_hash(), self.sim.state_hash())


class OutputFolderLock(unittest.TestCase):
    def test_run_into_a_held_folder_is_refused(self):
        out = work_dir("held")
        lock = os.path.join(out, "polydem.lock")
        # A lock naming a process that runs on this host (this process's parent) as its holder.
        text = "polydem output lock\npid %d\nhost %s\nstart_ticks -1\nstarted now\n" % (
            os.getppid(), socket.gethostname())

        def make():
            with open(lock, "w") as f:
                f.write(text)
        on_rank_zero(make)
        with self.assertRaises(polydem.Error) as raised:
            polydem.run(two_cubes(), out=out, snapshots=False)
        self.assertIn("output folder %s is in use: %s names process" % (out, lock),
                      str(raised.exception))
        barrier()
        self.assertEqual(os.listdir(out), ["polydem.lock"])
        with open(lock) as f:
            self.assertEqual(f.read(), text)

    def test_run_releases_its_lock(self):
        out = work_dir("released")
        polydem.run(two_cubes(), out=out, snapshots=False)
        barrier()
        self.assertFalse(os.path.exists(os.path.join(out, "polydem.lock")))
        self.assertTrue(os.path.exists(os.path.join(out, "summary.json")))


if __name__ == "__main__":
    unittest.main()

#!/usr/bin/python3
"""Checks python_coupling/scripts/checkpoint_summary.py on a checkpoint written by the C++ code
(2 ranks): the same counts, time, bounding box and kinetic energy as the C++ summary, the same
checksums and whole-file digest recomputed independently in Python, a damaged copy reported with
its dataset, edited copies (an attribute, an added dataset) refused by the digest, and a file of
format version 1 (no digest) summarised with a warning.

Usage: checkpoint_summary_test.py SCRIPT SAMPLE_DIR   (SAMPLE_DIR holds sample.h5, expected.json)
Exit 77 (ctest: skipped) when h5py is not installed.
"""
import json
import os
import shutil
import subprocess
import sys

try:
    import h5py  # noqa: F401
    import numpy  # noqa: F401
except ImportError:
    print("SKIP: /usr/bin/python3 has no h5py/numpy (Debian: python3-h5py)")
    sys.exit(77)


def run(script, path):
    out = subprocess.run([sys.executable, script, path, "--json", "-"], capture_output=True,
                         text=True)
    return out.returncode, out.stdout, out.stderr


def main(script, sample_dir):
    sample = os.path.join(sample_dir, "sample.h5")
    with open(os.path.join(sample_dir, "expected.json")) as f:
        expected = json.load(f)
    failures = []

    code, stdout, stderr = run(script, sample)
    if code != 0:
        failures.append("the script failed on a good file (%d): %s" % (code, stderr))
    got = json.loads(stdout)
    for key in ["step", "time", "dt", "stage", "particles", "replicated_particles", "pairs",
                "touching_pairs", "shapes", "materials", "writer_ranks", "scene_hash",
                "particles_lo", "particles_hi"]:
        if got.get(key) != expected[key]:
            failures.append("%s: python %r, C++ %r" % (key, got.get(key), expected[key]))
    e = expected["kinetic_energy"]
    if not abs(got["kinetic_energy"] - e) <= 1e-12 * abs(e):
        failures.append("kinetic energy: python %r, C++ %r" % (got["kinetic_energy"], e))
    if set(got["datasets"]) != set(expected["datasets"]):
        failures.append("dataset lists differ: %s" %
                        sorted(set(got["datasets"]) ^ set(expected["datasets"])))
    if got.get("digest") != expected["digest"]:
        failures.append("digest: python %s, C++ %s" % (got.get("digest"), expected["digest"]))
    for name, checksum in expected["datasets"].items():
        mine = got["datasets"].get(name, {})
        if mine.get("checksum") != checksum or not mine.get("ok"):
            failures.append("%s: python checksum %s, C++ %s" % (name, mine.get("checksum"),
                                                                checksum))
    if "step: %d" % expected["step"] not in stderr:
        failures.append("no step line in the text summary:\n" + stderr)

    # A damaged copy: one byte of /particles/velocity flipped.
    damaged = os.path.join(sample_dir, "damaged.h5")
    shutil.copyfile(sample, damaged)
    with h5py.File(damaged, "r") as f:
        offset = f["particles/velocity"].id.get_offset()
    with open(damaged, "r+b") as f:
        f.seek(offset + 100)
        byte = f.read(1)
        f.seek(offset + 100)
        f.write(bytes([byte[0] ^ 0x04]))
    code, stdout, stderr = run(script, damaged)
    if code != 1:
        failures.append("damaged file: exit status %d, expected 1" % code)
    if "dataset /particles/velocity is corrupted" not in stderr:
        failures.append("damaged file: /particles/velocity not named:\n" + stderr)
    others = [n for n, d in json.loads(stdout)["datasets"].items() if not d["ok"]]
    if others != ["/particles/velocity"]:
        failures.append("damaged file: datasets reported %s" % others)

    # Edited copies: each refused by the whole-file digest, exit status 1.
    def edited(name, edit, message):
        path = os.path.join(sample_dir, name + ".h5")
        shutil.copyfile(sample, path)
        with h5py.File(path, "r+") as f:
            edit(f)
        code, _, stderr = run(script, path)
        if code != 1 or message not in stderr:
            failures.append("%s: exit status %d, expected 1 and '%s':\n%s"
                            % (name, code, message, stderr))

    changed = "the file was changed after it was written"
    with h5py.File(sample, "r") as f:
        version = int(f.attrs["format_version"])

    def step(f):
        f["run"].attrs["step"] = numpy.int64(-5)

    edited("step", step, changed)
    edited("extra", lambda f: f.create_dataset("/particles/extra", data=[1.0, 2.0]), changed)
    edited("extra", lambda f: f.create_dataset("/particles/extra", data=[1.0, 2.0]),
           "dataset /particles/extra is not part of a version %d checkpoint" % version)

    # Version 2, before the digest (and the faces' joint planes of version 4, the joint laws'
    # history of version 5, the bolts of version 6): summarised, checksums verified, with a warning.
    def version2(f):
        del f["/shapes/face_plane"]
        del f["/subcontacts/law_state"]
        del f["/bolts"]
        del f.attrs["digest"]
        del f.attrs["digest_algorithm"]
        f.attrs["format_version"] = numpy.int32(2)

    old = os.path.join(sample_dir, "version2.h5")
    shutil.copyfile(sample, old)
    with h5py.File(old, "r+") as f:
        version2(f)
    code, _, stderr = run(script, old)
    if code != 0 or "digest: none (format version 2" not in stderr:
        failures.append("version 2: exit status %d:\n%s" % (code, stderr))

    for f in failures:
        print("FAIL:", f)
    print("checkpoint_summary.py: %d datasets checked, %s" %
          (len(expected["datasets"]), "ok" if not failures else "%d failures" % len(failures)))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))

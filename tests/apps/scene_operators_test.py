#!/usr/bin/python3
"""A user force operator named in the scene ([[operator]], docs/scene-format.md "Operators").

Two cubes fall freely; the scene names the operator "uplift" from a small library
(tests/apps/operators/uplift_operators.cpp) that lifts the second with half its weight. The
leapfrog integrates a constant acceleration exactly, so after the run the first has dropped
g t^2 / 2 and the second (g / 2) t^2 / 2, to rounding (g from the scene written here). The
operator's timer is in summary.json under its name, between "bolts" and "force ratio"; the run has
the same state hash on 1 and 3 ranks. A name the library does not define, a library that does not
load and an operator without a library (the command line supplies none) end with exit status 1 and
the scene's file:line.

Usage: scene_operators_test.py POLYDEM MPIEXEC LIBRARY WORKDIR
"""
import csv
import json
import os
import shutil
import subprocess
import sys

G = 9.81
HEIGHT = 5.0
STEPS = 400
DT = 1e-4

SCENE = f"""
[scene]
id = "T-SCENE-OPERATOR"
title = "Two cubes falling, one lifted by a named operator"

[simulation]
kernel = "gjk-epa-ipm"
dt = "{DT} s"
steps = {STEPS}
gravity = [0, 0, -{G}]

[domain]
min = [-10, -10, -10]
max = [10, 10, 10]
blocks = [3, 1, 1]

[output]
monitor = ["plain", "lifted"]

[[material]]
name = "rock"
density = "2650 kg/m^3"
kn = "1 GN/m"
ks = "0.5 GN/m"
penalty = "0.5 GPa"

[[shape]]
name = "cube"
type = "box"
size = [1, 1, 1]

[[particle]]
label = "plain"
shape = "cube"
material = "rock"
position = [-6, 0, {HEIGHT}]

[[particle]]
label = "lifted"
shape = "cube"
material = "rock"
position = [6, 0, {HEIGHT}]
"""

failures = []


def expect(ok, message):
    print(("ok   " if ok else "FAIL ") + message)
    if not ok:
        failures.append(message)


def write_scene(name, operator_lines):
    """The scene with `operator_lines` appended, named as polydem is given it (relative to WORK,
    where it runs: a library named without a folder is then found in the scene's folder), and
    the line of its [[operator]] header."""
    with open(os.path.join(WORK, name), "w") as f:
        f.write(SCENE + "\n" + operator_lines)
    return name, (SCENE + "\n").count("\n") + 1


def run(scene, out, ranks=1):
    cmd = [POLYDEM, "run", scene, "--out", out, "--no-snapshots", "--quiet"]
    if ranks > 1:
        cmd = [MPIEXEC, "-n", str(ranks), "--oversubscribe"] + cmd
    return subprocess.run(cmd, cwd=WORK, capture_output=True, text=True, timeout=300)


def last_row(out):
    with open(os.path.join(out, "series.csv")) as f:
        rows = list(csv.DictReader(f))
    return rows[-1]


def check_run():
    scene, _ = write_scene("lifted.toml",
                           '[[operator]]\nname = "uplift"\nlibrary = "libuplift_operators.so"\n')
    one = run(scene, os.path.join(WORK, "one"))
    expect(one.returncode == 0, f"run on 1 rank exits 0 ({one.stderr.strip()[-300:]})")
    if one.returncode != 0:
        return
    three = run(scene, os.path.join(WORK, "three"), ranks=3)
    expect(three.returncode == 0, f"run on 3 ranks exits 0 ({three.stderr.strip()[-300:]})")
    row = last_row(os.path.join(WORK, "one"))
    t = float(row["time"])
    expect(abs(t - STEPS * DT) <= 1e-12, f"ran to t = {t} s")
    for label, a in (("plain", G), ("lifted", 0.5 * G)):
        drop = HEIGHT - float(row[f"{label}_z"])
        expected = 0.5 * a * t * t
        expect(abs(drop - expected) <= 1e-9 * expected,
               f"{label}: dropped {drop:.12f} m, (a t^2 / 2) {expected:.12f} m with a = {a}")
    summary = json.load(open(os.path.join(WORK, "one", "summary.json")))
    names = [r["name"] for r in summary["timing"]]
    expect("uplift" in names, f"timer 'uplift' in summary.json ({names})")
    if "uplift" in names:
        k = names.index("uplift")
        expect(names[k - 1] == "bolts" and names[k + 1] == "force ratio",
               "'uplift' timed between 'bolts' and 'force ratio'")
        expect(summary["timing"][k]["count"] == STEPS, "'uplift' timed once per step")
    if three.returncode == 0:
        h1 = summary["state_hash"]
        h3 = json.load(open(os.path.join(WORK, "three", "summary.json")))["state_hash"]
        expect(h1 == h3, f"same state hash on 1 and 3 ranks ({h1}, {h3})")


def check_error(name, operator_lines, words):
    scene, line = write_scene(name + ".toml", operator_lines)
    r = run(scene, os.path.join(WORK, name))
    where = f"{scene}:{line}:"
    expect(r.returncode == 1, f"{name}: exit status 1 (got {r.returncode})")
    expect(where in r.stderr and all(w in r.stderr for w in words),
           f"{name}: message names {where} and {words}: {r.stderr.strip()}")
    expect(not os.path.exists(os.path.join(WORK, name, "summary.json")),
           f"{name}: no summary.json")


def main():
    global POLYDEM, MPIEXEC, WORK
    POLYDEM, MPIEXEC, library, WORK = sys.argv[1:5]
    shutil.rmtree(WORK, ignore_errors=True)
    os.makedirs(WORK)
    # The scene names the library relative to its own folder.
    shutil.copy(library, os.path.join(WORK, "libuplift_operators.so"))
    check_run()
    check_error("unknown_name",
                '[[operator]]\nname = "no_such_operator"\nlibrary = "libuplift_operators.so"\n',
                ["no_such_operator", "defines no operator"])
    check_error("missing_library",
                '[[operator]]\nname = "uplift"\nlibrary = "libnot_there.so"\n',
                ["libnot_there.so", "does not load"])
    check_error("no_library", '[[operator]]\nname = "uplift"\n',
                ["uplift", "names no library"])
    print(f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""benchmark_scenes/tools/tilt_study.py: its onset is the start of the motion that fails the
slope (not an earlier slip that jams), its mode is read as the `tilt_failure` check reads it (the
slope's median turn), and its stepped bases hold the columns where they were put:
over the first 0.1 s of settling (the tilt starts at 0.5 s) no block moves 1e-3 of its size (a
tread 1 cm too low would let a column fall it in 45 ms; one too high would push it off).

usage: tilt_study_test.py POLYDEM REPO_ROOT WORK_DIR
"""
import math
import os
import shutil
import subprocess
import sys

SETTLE = 0.1  # s of the settling before the tilt that the test runs


def check_onset(ts):
    v_min = ts.EPS * math.sqrt(9.81 * ts.EDGE)
    # (tilt deg, largest displacement m, largest speed m/s): creep, a 2 mm slip that jams at
    # 10 deg, rest, then the motion that reaches 5 cm from 12 deg on.
    history = [(0.1 * i, 1e-5 * i, 0.01 * v_min) for i in range(100)]
    history += [(10.0, 2.5e-3, 20 * v_min), (10.1, 2.6e-3, 0.1 * v_min)]
    history += [(10.2 + 0.1 * i, 2.6e-3, 0.1 * v_min) for i in range(18)]
    history += [(12.0 + 0.1 * i, 2.6e-3 + 0.01 * i, 2 * v_min * (i + 1)) for i in range(8)]
    onset = ts.onset_angle(history)
    if abs(onset - 12.0) > 1e-9:
        sys.exit(f"FAIL: onset {onset} deg, expected 12.0 (the sustained motion, not the slip)")
    if not math.isnan(ts.onset_angle(history[:120])):
        sys.exit("FAIL: an onset without a block having moved 5 cm")
    print("onset: the start of the sustained motion (12.0 deg), not the jammed slip (10.0)")


def check_mode(ts):
    # The state of slope 3 when its first block had moved 5 cm (as the SlopeTurn test of
    # tests/run/motion_checks_test.cpp): the top cube slid off a leaning column without turning.
    moves = [(0.05, 0.0, 1.0)] + [(0.008 * (i + 1), 6.0, 1.0) for i in range(5)]
    moves += [(0.007 * (i + 1), 4.5, 1.0) for i in range(5)]
    moves += [(0.0003 * i, 0.1 * i, 1.0) for i in range(10)]
    turn = ts.slope_turn(moves)
    if turn != 4.5:
        sys.exit(f"FAIL: the slope's turn is {turn} deg, expected 4.5 (the check's reading)")
    print("mode: the slope's turn 4.5 deg (toppling), its first block's 0 deg")


def check_settles(ts, polydem, work, case):
    text, labels = ts.scene(case)
    path = os.path.join(work, f"{case}.toml")
    with open(path, "w") as f:
        f.write(text)
    out = os.path.join(work, case)
    shutil.rmtree(out, ignore_errors=True)
    subprocess.run([polydem, "run", path, "--out", out, "--no-snapshots", "--quiet",
                    "--end-time", str(SETTLE)], check=True)
    import csv
    with open(os.path.join(out, "series.csv")) as f:
        rows = list(csv.DictReader(f))
    first, last = rows[0], rows[-1]
    moved = max(math.dist([float(first[f"{lab}_{a}"]) for a in "xyz"],
                          [float(last[f"{lab}_{a}"]) for a in "xyz"]) for lab in labels)
    print(f"{case}: {len(labels)} blocks settled, the largest moved {moved:.2e} m in "
          f"{SETTLE} s")
    if not moved < 1e-3 * ts.EDGE:
        sys.exit(f"FAIL: {case}: a block moved {moved} m before the tilt (limit {1e-3 * ts.EDGE})")


def main():
    polydem, root, work = sys.argv[1:4]
    sys.path.insert(0, os.path.join(root, "benchmark_scenes", "tools"))
    import tilt_study as ts
    os.makedirs(work, exist_ok=True)
    check_onset(ts)
    check_mode(ts)
    for case in ("stepped-gjk-0.03", "columns5-gjk-0.03", "s1-stepped-gjk-0.03"):
        check_settles(ts, polydem, work, case)
    print("PASS")


if __name__ == "__main__":
    main()

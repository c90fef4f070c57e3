#!/usr/bin/python3
"""Test of python_coupling/plots/plot_series.py on a run directory made here.

Usage: /usr/bin/python3 plot_series_test.py PATH/TO/plot_series.py WORK_DIR
"""
import importlib.util
import json
import math
import os
import shutil
import subprocess
import sys

import numpy as np

sys.dont_write_bytecode = True  # importing the script under test must not litter the source tree


def load(path):
    spec = importlib.util.spec_from_file_location("plot_series", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def make_run(run_dir):
    """A sliding block (Zhao eq. 41 shape: s = v0 t - a t^2 / 2) with a small numerical error."""
    os.makedirs(run_dir)
    v0, a = 6.0, 3.2
    with open(os.path.join(run_dir, "series.csv"), "w") as f:
        f.write("time,step,kinetic_energy,block_x,block_x_analytic,block_vx,block_vx_analytic\n")
        for step in range(0, 201, 10):
            t = step * 1e-3
            s, v = v0 * t - 0.5 * a * t * t, v0 - a * t
            f.write("%.17g,%d,%.17g,%.17g,%.17g,%.17g,%.17g\n"
                    % (t, step, 0.5 * v * v, s * (1 + 1e-3), s, v * (1 - 2e-4), v))
        f.write("0.21,21,1.0")  # a torn last row (run still writing)
    summary = {"id": "D-SLIDING-BLOCK", "title": "block on a 30 deg incline",
               "series_units": {"kinetic_energy": "J/kg"},
               "checks": [{"name": "displacement", "pass": True},
                          {"name": "velocity", "pass": False}]}
    with open(os.path.join(run_dir, "summary.json"), "w") as f:
        json.dump(summary, f)


def run(script, *args):
    return subprocess.run([sys.executable, script] + list(args), capture_output=True, text=True)


def is_png(path):
    with open(path, "rb") as f:
        return f.read(8) == b"\x89PNG\r\n\x1a\n" and os.path.getsize(path) > 10000


def main():
    script, work = sys.argv[1], sys.argv[2]
    shutil.rmtree(work, ignore_errors=True)
    run_dir = os.path.join(work, "run")
    make_run(run_dir)
    m = load(script)

    # Helpers.
    err = m.relative_error(np.array([1.01, 2.0, 5.0]), np.array([1.0, 0.0, -4.0]))
    assert abs(err[0] - 0.01) < 1e-12 and math.isnan(err[1]) and abs(err[2] - 2.25) < 1e-15, err
    assert m.unit_of("block_vx", {}) == "m/s" and m.unit_of("block_x", {}) == "m"
    assert m.unit_of("time", {}) == "s" and m.unit_of("kinetic_energy", {"kinetic_energy": "J/kg"}) == "J/kg"
    assert m.unit_of("mystery", {}) is None
    header, series = m.read_series(os.path.join(run_dir, "series.csv"))
    assert len(series["time"]) == 21, len(series["time"])  # torn row skipped
    assert m.choose_columns(header, "time", None) == ["kinetic_energy", "block_x", "block_vx"]
    # Default panels: a block's x, y, z together (not when one has an analytical partner), its
    # vx, vy, vz, all rotations, and kinetic energy with the force ratio.
    columns = ["kinetic_energy", "contacts", "force_ratio", "b_x", "b_y", "b_z", "b_vx", "b_vy",
               "b_vz", "b_rotation", "c_x", "c_y", "c_z", "c_x_analytic", "c_rotation"]
    assert m.group_panels(columns) == [
        ["kinetic_energy", "force_ratio"], ["contacts"], ["b_x", "b_y", "b_z"],
        ["b_vx", "b_vy", "b_vz"], ["b_rotation", "c_rotation"], ["c_x"], ["c_y"], ["c_z"],
        ["c_x_analytic"]], m.group_panels(columns)
    summary = m.read_summary(run_dir)
    assert m.title_of(summary, run_dir).endswith("checks: 1 of 2 pass (failed: velocity)")

    # The command line as a user runs it (once: starting matplotlib is the slow part).
    r = run(script, run_dir)
    assert r.returncode == 0, r.stderr
    assert is_png(os.path.join(run_dir, "series.png"))
    # Chosen columns and output file; an unknown column is an error naming it.
    out = os.path.join(work, "x.png")
    assert m.main([run_dir, "--columns", "block_x", "--out", out]) == 0
    assert is_png(out)
    try:
        m.main([run_dir, "--columns", "block_x,nope"])
        raise AssertionError("no error for an unknown column")
    except SystemExit as e:
        assert "nope" in str(e.code), e.code
    print("ok")


if __name__ == "__main__":
    main()

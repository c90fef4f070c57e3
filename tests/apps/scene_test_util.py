"""What the scene checks of tests/apps share: failures collected by expect(), running polydem,
reading a factor of safety, a plane's normal from dip and dip direction, quantities with units,
and the command line `SCRIPT POLYDEM MODE SCENE WORKDIR`."""

import json
import math
import os
import shutil
import subprocess
import sys

import numpy as np

FAILURES = []


def expect(ok, message):
    if not ok:
        FAILURES.append(message)
        print("FAIL:", message)


def run(cmd, workdir):
    """Runs cmd in workdir; stops the test with its output when it fails."""
    out = subprocess.run(cmd, cwd=workdir, capture_output=True, text=True)
    if out.returncode != 0:
        print(out.stdout[-3000:], out.stderr[-3000:])
        sys.exit(f"{cmd[:2]} failed with exit status {out.returncode}")
    return out


def fos(polydem, scene, workdir, out="fos"):
    """polydem fos on scene into workdir/out; the factor of safety of its fos.json."""
    run([polydem, "fos", scene, "--out", out, "--quiet"], workdir)
    with open(os.path.join(workdir, out, "fos.json")) as f:
        return json.load(f)["factor_of_safety"]


def normal_from_dip(dip, dip_direction):
    """Upward unit normal of a plane (degrees; x east, y north, z up)."""
    d, a = math.radians(dip), math.radians(dip_direction)
    return np.array([math.sin(d) * math.sin(a), math.sin(d) * math.cos(a), math.cos(d)])


def quantity(text, units):
    """'10 kPa' -> 10000.0 with units {'kPa': 1e3, ...}; a plain number as it is."""
    if isinstance(text, (int, float)):
        return float(text)
    number, unit = text.split()
    return float(number) * units[unit]


def metres(value):
    """'4.5 m', '450 cm', 4.5 or '4.5' -> 4.5."""
    if isinstance(value, str) and len(value.split()) == 1:
        value = float(value)
    return quantity(value, {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "km": 1e3})


def main_by_mode(checks):
    """SCRIPT POLYDEM MODE SCENE WORKDIR: runs checks[MODE](polydem, scene, workdir) in a fresh
    WORKDIR and exits non-zero when an expect() failed."""
    polydem, mode, scene, workdir = sys.argv[1:5]
    polydem, scene, workdir = (os.path.abspath(p) for p in (polydem, scene, workdir))
    shutil.rmtree(workdir, ignore_errors=True)
    os.makedirs(workdir)
    checks[mode](polydem, scene, workdir)
    if FAILURES:
        sys.exit(f"{len(FAILURES)} check(s) failed")
    print("all checks passed")

#!/usr/bin/python3
"""E-PSEUDO-STATIC against the pseudo-static method, computed from the scene file.

`polydem fos` on a block on an incline under [seismic] kh (azimuth) and kv must find the seismic
factor of safety within 1 %. With the body acceleration a = g (kh sin az, kh cos az, kv - 1) and
the incline's outward normal n, the block holds while the friction tan(phi / F) on the normal load
-a.n balances the load along the plane |a - (a.n) n|:

  F = (-a.n) tan phi / |a - (a.n) n|,

which for a load out of the slope (azimuth = dip direction) and kv = 0 is Hoek and Bray's
F = (cos theta - kh sin theta) tan phi / (sin theta + kh cos theta); both are printed.

Usage: seismic_scene_test.py POLYDEM SCENE WORKDIR
"""
import json
import math
import os
import shutil
import subprocess
import sys
import tomllib

import numpy as np


def incline_normal(scene):
    """The outward normal of the fixed box's top face: +z turned by the box's rotation about +y."""
    fixed = next(p for p in scene["particle"] if p.get("fixed"))
    shape = next(s for s in scene["shape"] if s["name"] == fixed["shape"])
    rotation = shape["rotation"]
    assert rotation["axis"] == [0, 1, 0], "the incline is turned about +y"
    theta = math.radians(rotation["angle"])
    return theta, np.array([math.sin(theta), 0.0, math.cos(theta)])


def main(polydem, scene_file, workdir):
    scene = tomllib.loads(open(scene_file).read())
    seismic = scene["seismic"]
    kh, kv = seismic.get("kh", 0.0), seismic.get("kv", 0.0)
    az = math.radians(seismic.get("azimuth", 0.0))
    theta, n = incline_normal(scene)
    tan_phi = math.tan(math.radians(scene["material"][0]["friction_angle"]))
    a = np.array([kh * math.sin(az), kh * math.cos(az), kv - 1.0])  # per unit g
    normal = -a @ n
    along = np.linalg.norm(a - (a @ n) * n)
    expected = normal * tan_phi / along
    textbook = ((math.cos(theta) - kh * math.sin(theta)) * tan_phi /
                (math.sin(theta) + kh * math.cos(theta)))

    shutil.rmtree(workdir, ignore_errors=True)
    os.makedirs(workdir)
    out = subprocess.run([polydem, "fos", scene_file, "--out", "out", "--quiet"], cwd=workdir,
                         capture_output=True, text=True)
    if out.returncode != 0:
        print(out.stdout[-3000:], out.stderr[-3000:])
        sys.exit(f"polydem fos failed with exit status {out.returncode}")
    with open(os.path.join(workdir, "out", "fos.json")) as f:
        measured = json.load(f)["factor_of_safety"]
    print(f"kh = {kh}, azimuth = {math.degrees(az)} deg, kv = {kv}, theta = "
          f"{math.degrees(theta):.4g} deg: F = {measured}, expected {expected:.4f} "
          f"(Hoek and Bray with kv = 0 out of the slope: {textbook:.4f}), static "
          f"{tan_phi / math.tan(theta):.4f}")
    if measured is None or abs(measured - expected) > 0.01 * expected:
        sys.exit(f"FAIL: F = {measured}, expected {expected:.4f} within 1 %")


if __name__ == "__main__":
    main(*sys.argv[1:4])

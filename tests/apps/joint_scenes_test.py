#!/usr/bin/python3
"""Joints of a rock mass, from a scene file to the contact table and the factor of safety.

contacts SCENE: runs `polydem run` on J-JOINTED-MASS and reads the last snapshot's contact table
  (/contacts/joint, /contacts/normal). Every contact that took a joint lies on a plane of that
  joint (its normal parallel to the joint's planes); every joint carries contacts; of the contacts
  on a plane that names a joint (normal parallel to it), most take that joint (the rest are
  corners and edges of blocks, which fall back to the material pair); and no contact on the set
  that names no joint takes one.
wedge SCENE: `polydem fos` on J-WEDGE-JOINTS: F within 1 % of Hoek and Bray's vector method for
  the two planes and their friction angles, read from the scene.
planar SCENE: `polydem fos` on J-PLANAR-COHESION: F within 2 % of the limit-equilibrium formula
  F = (c A + W cos(psi) tan(phi)) / (W sin(psi)), with A, W from the scene's box and base plane.

Usage: joint_scenes_test.py POLYDEM MODE SCENE WORKDIR
"""
import glob
import json
import math
import os
import shutil
import subprocess
import sys
import tomllib

import h5py
import numpy as np

FAILURES = []


def expect(ok, message):
    if not ok:
        FAILURES.append(message)
        print("FAIL:", message)


def normal_from_dip(dip, dip_direction):
    d, a = math.radians(dip), math.radians(dip_direction)
    return np.array([math.sin(d) * math.sin(a), math.sin(d) * math.cos(a), math.cos(d)])


def run(cmd, workdir):
    out = subprocess.run(cmd, cwd=workdir, capture_output=True, text=True)
    if out.returncode != 0:
        print(out.stdout[-3000:], out.stderr[-3000:])
        sys.exit(f"{cmd[:2]} failed with exit status {out.returncode}")
    return out


def fos(polydem, scene, workdir):
    run([polydem, "fos", scene, "--out", "fos", "--quiet"], workdir)
    with open(os.path.join(workdir, "fos", "fos.json")) as f:
        return json.load(f)["factor_of_safety"]


def check_contacts(polydem, scene_file, workdir):
    scene = tomllib.load(open(scene_file, "rb"))
    joints = [j["name"] for j in scene["joint"]]
    mass = scene["rock_mass"][0]
    # The planes of each joint (by index into [[joint]]), and the planes that name none.
    planes = {}  # name -> (normal, joint index or -1)
    for p in mass.get("plane", []) + mass.get("joint_set", []):
        joint = joints.index(p["joint"]) if "joint" in p else -1
        planes[p["name"]] = (normal_from_dip(p["dip"], p["dip_direction"]), joint)
    run([polydem, "run", scene_file, "--out", "run", "--quiet"], workdir)
    last = sorted(glob.glob(os.path.join(workdir, "run", "snapshots", "snapshot_*.h5")))[-1]
    with h5py.File(last, "r") as h:
        joint = h["/contacts/joint"][()]
        normal = h["/contacts/normal"][()]
    print(f"{last}: {len(joint)} contacts, joints used {np.bincount(joint + 1)} (first: none)")
    parallel = {name: np.abs(normal @ n) > 1 - 1e-6 for name, (n, _) in planes.items()}
    for j, name in enumerate(joints):
        on_joint = joint == j
        expect(on_joint.sum() >= 5, f"joint '{name}': only {on_joint.sum()} contacts take it")
        own = np.zeros(len(joint), bool)
        for plane, (_, pj) in planes.items():
            if pj == j:
                own |= parallel[plane]
        stray = on_joint & ~own
        expect(not stray.any(), f"joint '{name}': {stray.sum()} contacts off its planes take it")
    for plane, (_, pj) in planes.items():
        on_plane = parallel[plane]
        if pj < 0:
            expect(not (joint[on_plane] >= 0).any(),
                   f"plane '{plane}' names no joint, but {np.sum(joint[on_plane] >= 0)} of its "
                   "contacts took one")
            continue
        share = np.mean(joint[on_plane] == pj) if on_plane.any() else 0.0
        print(f"plane '{plane}': {on_plane.sum()} contacts, {share:.0%} take joint '{joints[pj]}'")
        expect(share >= 0.95, f"plane '{plane}': only {share:.0%} of its contacts take its joint")


def vector_method(scene_file):
    """Hoek and Bray's wedge, dry, frictional: F from the two planes' normals and friction."""
    scene = tomllib.load(open(scene_file, "rb"))
    friction = {j["name"]: math.radians(j["friction_angle"]) for j in scene["joint"]}
    a, b = scene["rock_mass"][0]["plane"]
    na, nb = normal_from_dip(a["dip"], a["dip_direction"]), normal_from_dip(b["dip"], b["dip_direction"])
    i = np.cross(na, nb)
    i /= np.linalg.norm(i)
    if i[2] > 0:
        i = -i  # down the line of intersection
    w = np.array([0.0, 0.0, -1.0])
    n_a, n_b, _ = np.linalg.solve(np.column_stack([na, nb, i]), -w)
    assert n_a > 0 and n_b > 0, "the wedge must rest on both planes"
    return (n_a * math.tan(friction[a["joint"]]) + n_b * math.tan(friction[b["joint"]])) / (w @ i)


def limit_equilibrium(scene_file):
    """Planar slide on the base plane, east of the release plane x = 0, up to the box's top."""
    scene = tomllib.load(open(scene_file, "rb"))
    mass = scene["rock_mass"][0]
    base = next(p for p in mass["plane"] if p["name"] == "base")
    joint = next(j for j in scene["joint"] if j["name"] == base["joint"])
    assert base["point"] == [0, 0, 0] and base["dip_direction"] == 90
    (x0, y0, _), (x1, y1, z1) = mass["region"]["min"], mass["region"]["max"]
    psi = math.radians(base["dip"])
    phi = math.radians(joint["friction_angle"])
    cohesion = float(joint["cohesion"].split()[0]) * {"kPa": 1e3, "Pa": 1.0}[joint["cohesion"].split()[1]]
    width, length = y1 - y0, x1  # the block spans x = 0 .. x1 above z = -x tan(psi), below z1
    area = width * length / math.cos(psi)
    volume = width * (length * z1 + length**2 * math.tan(psi) / 2)
    rho = float(scene["material"][0]["density"].split()[0])
    weight = rho * 9.81 * volume
    return (cohesion * area + weight * math.cos(psi) * math.tan(phi)) / (weight * math.sin(psi))


def main():
    polydem, mode, scene, workdir = sys.argv[1:5]
    polydem = os.path.abspath(polydem)
    scene = os.path.abspath(scene)
    shutil.rmtree(workdir, ignore_errors=True)
    os.makedirs(workdir)
    if mode == "contacts":
        check_contacts(polydem, scene, workdir)
    else:
        expected, tolerance = (vector_method(scene), 0.01) if mode == "wedge" else \
            (limit_equilibrium(scene), 0.02)
        f = fos(polydem, scene, workdir)
        error = abs(f - expected) / expected
        print(f"{mode}: F = {f}, expected {expected:.4f} ({error:.2%}, tolerance {tolerance:.0%})")
        expect(error <= tolerance, f"{mode}: F = {f}, expected {expected:.4f} within {tolerance:.0%}")
    if FAILURES:
        sys.exit(f"{len(FAILURES)} failure(s)")
    print("all checks passed")


if __name__ == "__main__":
    main()

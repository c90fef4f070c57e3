#!/usr/bin/python3
"""Joints of a rock mass, from a scene file to the contact table and the factor of safety.

contacts SCENE: runs `polydem run` on J-JOINTED-MASS and reads the last snapshot's contact table
  (/contacts/joint, /contacts/normal). Every contact that took a joint lies on a plane of that
  joint (its normal parallel to the joint's planes); every joint carries contacts; of the contacts
  on a plane that names a joint (normal parallel to it), most take that joint (the rest are
  corners and edges of blocks, which fall back to the material pair); and no contact on the set
  that names no joint takes one.
faces SCENE [MPIEXEC]: runs `polydem run` on J-JOINTED-MASS (on 1 rank, and on 2 with MPIEXEC)
  and reads the first snapshot's faces (/mesh, /faces/joint), written before any step, where every
  face made by a plane lies on it exactly: each face on a plane of the scene (a [[rock_mass.plane]]
  or a plane of a joint set, from its dip, dip direction, point or origin and spacing) carries
  that plane's joint, every other face (the region's surface, the set that names none) -1; every
  joint colours faces; the root attribute joint_names lists the scene's [[joint]] names; the
  table is the same on 2 ranks; snapshots.xmf describes /faces/joint as cell data.
wedge SCENE: `polydem fos` on J-WEDGE-JOINTS: F within 1 % of Hoek and Bray's vector method for
  the two planes and their friction angles, read from the scene.
planar SCENE: `polydem fos` on J-PLANAR-COHESION: F within 2 % of the limit-equilibrium formula
  F = (c A + W cos(psi) tan(phi)) / (W sin(psi)), with A, W from the scene's box and base plane.

Usage: joint_scenes_test.py POLYDEM MODE SCENE WORKDIR [MPIEXEC]
"""
import glob
import math
import os
import shutil
import sys
import tomllib

import h5py
import numpy as np
from scene_test_util import FAILURES, expect, fos, metres, normal_from_dip, run

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


def scene_planes(scene):
    """Every plane family of the scene's rock mass: (name, unit normal, offset of one plane,
    spacing or None for a single plane, joint index or -1)."""
    joints = [j["name"] for j in scene["joint"]]
    mass = scene["rock_mass"][0]
    out = []
    for p in mass.get("plane", []) + mass.get("joint_set", []):
        n = normal_from_dip(p["dip"], p["dip_direction"])
        point = np.array(p.get("point", p.get("origin", [0, 0, 0])), float)
        spacing = metres(p["spacing"]) if "spacing" in p else None
        out.append((p["name"], n, n @ point, spacing, joints.index(p["joint"]) if "joint" in p
                    else -1))
    return out


def read_faces(path):
    with h5py.File(path, "r") as h:
        points, topology = h["/mesh/points"][()], h["/mesh/topology"][()]
        joint = h["/faces/joint"][()]
        names = h.attrs["joint_names"]
        names = names.decode() if isinstance(names, bytes) else str(names)
    faces, i = [], 0
    while i < len(topology):  # XDMF Mixed: 3 (polygon), vertex count, indices
        n = int(topology[i + 1])
        faces.append(points[topology[i + 2:i + 2 + n]])
        i += 2 + n
    return faces, joint, names.split("\n") if names else []


def expected_joint(face, planes, tolerance):
    """The joint of the plane that `face` lies on (-1: on none of them)."""
    normal = np.cross(face[1] - face[0], face[2] - face[0])
    normal /= np.linalg.norm(normal)
    for name, n, offset, spacing, joint in planes:
        if abs(normal @ n) < 1 - 1e-9:
            continue
        d = face @ n - offset
        if spacing is not None:
            d -= spacing * np.round(d.mean() / spacing)
        if np.abs(d).max() <= tolerance:
            return joint, name
    return -1, None


def check_faces(polydem, scene_file, workdir, mpiexec):
    scene = tomllib.load(open(scene_file, "rb"))
    joints = [j["name"] for j in scene["joint"]]
    planes = scene_planes(scene)
    lo, hi = (np.array(scene["rock_mass"][0]["region"][k], float) for k in ("min", "max"))
    tolerance = 1e-9 * np.linalg.norm(hi - lo)  # round-off of the cut, relative to the mass
    tables = []
    runs = [("run1", [polydem])] + ([("run2", [mpiexec, "-n", "2", "--oversubscribe", polydem])]
                                     if mpiexec else [])
    for out, command in runs:
        # One step: the faces are checked in the first snapshot, written before any step.
        run(command + ["run", scene_file, "--out", out, "--quiet", "--steps", "1"], workdir)
        first = sorted(glob.glob(os.path.join(workdir, out, "snapshots", "snapshot_*.h5")))[0]
        tables.append(read_faces(first))
    faces, joint, names = tables[0]
    expect(names == joints, f"joint_names {names}, the scene's [[joint]] names are {joints}")
    wrong, per_plane = 0, {}
    for face, j in zip(faces, joint):
        want, plane = expected_joint(face, planes, tolerance)
        per_plane[plane] = per_plane.get(plane, 0) + 1
        if j != want:
            wrong += 1
            if wrong <= 5:
                print(f"face on {plane or 'no plane'} carries joint {j}, expected {want}")
    print(f"{len(faces)} faces, per plane {per_plane}, joints used {np.bincount(joint + 1)}")
    expect(wrong == 0, f"{wrong} of {len(faces)} faces carry another joint than their plane's")
    for name, _, _, _, j in planes:
        expect(per_plane.get(name, 0) > 0, f"no face lies on plane '{name}'")
    for j, name in enumerate(joints):
        expect(np.sum(joint == j) > 0, f"no face carries joint '{name}'")
    expect(per_plane.get(None, 0) > 0 and np.all(joint >= -1), "faces on no plane exist")
    for faces2, joint2, _ in tables[1:]:
        expect(len(faces2) == len(faces) and np.array_equal(joint2, joint),
               "the 2-rank run's face joints differ from the 1-rank run's")
    xmf = open(os.path.join(workdir, "run1", "snapshots.xmf")).read()
    expect('Attribute Name="joint" AttributeType="Scalar" Center="Cell"' in xmf
           and ":/faces/joint</DataItem>" in xmf, "snapshots.xmf does not describe /faces/joint")


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
    elif mode == "faces":
        check_faces(polydem, scene, workdir, sys.argv[5] if len(sys.argv) > 5 else None)
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

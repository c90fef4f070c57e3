#!/usr/bin/python3
"""render_frames.py on snapshots written here with h5py (the layout of docs/output-files.md).

- The view looks at the slope's face: a fixed slope whose face looks towards azimuth theta (east,
  north, south-west, ...) gives the camera azimuth theta + FACE_OFFSET within 1e-9 deg, with a free
  block on it; a rock mass whose free blocks' joint faces point elsewhere is seen from its cut
  face; a flat floor gives the default azimuth.
- Each field (speed, displacement, joint) renders a PNG; the joint legend names the joints of
  the snapshot's joint_names attribute that colour a free face, and "no joint"; an unknown field
  and a missing field are refused with a message.

Usage: render_frames_test.py RENDER_FRAMES.py WORKDIR
"""
import importlib.util
import math
import os
import shutil
import sys

import h5py
import numpy as np

FAILURES = []


def expect(ok, message):
    if not ok:
        FAILURES.append(message)
        print("FAIL:", message)


def load(path):
    spec = importlib.util.spec_from_file_location("render_frames", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def outward(vertices, faces):
    """The faces of a convex body as vertex-index lists, counter-clockwise seen from outside."""
    centre = vertices.mean(axis=0)
    out = []
    for f in faces:
        p = vertices[f]
        normal = 0.5 * np.cross(p, np.roll(p, -1, axis=0)).sum(axis=0)
        out.append(list(f) if normal @ (p.mean(axis=0) - centre) > 0 else list(f)[::-1])
    return out


def prism(profile, y0, y1):
    """A prism: the (x, z) polygon `profile` (counter-clockwise) extruded from y0 to y1."""
    n = len(profile)
    vertices = np.array([[x, y, z] for y in (y0, y1) for x, z in profile], float)
    faces = [list(range(n)), list(range(n, 2 * n))]
    faces += [[k, (k + 1) % n, n + (k + 1) % n, n + k] for k in range(n)]
    return vertices, outward(vertices, faces)


def prism_x(profile, x0, x1):
    """A prism: the (y, z) polygon `profile` extruded from x0 to x1."""
    v, f = prism(profile, x0, x1)
    return v[:, [1, 0, 2]], outward(v[:, [1, 0, 2]], f)


def box(lo, hi):
    return prism([(lo[0], lo[2]), (hi[0], lo[2]), (hi[0], hi[2]), (lo[0], hi[2])], lo[1], hi[1])


def rotated(vertices, degrees):
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    return vertices @ np.array([[c, s, 0], [-s, c, 0], [0, 0, 1]])


class Body:
    def __init__(self, vertices, faces, fixed, velocity=(0, 0, 0), joints=None):
        self.vertices, self.faces, self.fixed = vertices, faces, fixed
        self.velocity = np.array(velocity, float)
        self.joints = joints if joints is not None else [-1] * len(faces)


def write_snapshot(path, bodies, step=0, joint_names=(), fields=("fixed", "joint",
                                                                 "displacement", "pressure")):
    points, topology, face_count, velocity = [], [], [], []
    fixed, joint, displacement = [], [], []
    for b in bodies:
        first = len(points)
        points.extend(b.vertices)
        for f, j in zip(b.faces, b.joints):
            topology += [3, len(f)] + [first + i for i in f]
            fixed.append(1 if b.fixed else 0)
            joint.append(j)
            displacement.append(b.velocity * step)
        face_count.append(len(b.faces))
        velocity.append(b.velocity)
    with h5py.File(path, "w") as h:
        h.attrs["format"] = "polydem-snapshot"
        h.attrs["step"] = step
        h.attrs["time"] = 0.01 * step
        h.attrs["joint_names"] = "\n".join(joint_names)
        h["mesh/points"] = np.array(points, float)
        h["mesh/topology"] = np.array(topology, np.int64)
        h["particles/face_count"] = np.array(face_count, np.int64)
        h["particles/velocity"] = np.array(velocity, float)
        if "fixed" in fields:
            h["faces/fixed"] = np.array(fixed, np.uint8)
        if "joint" in fields:
            h["faces/joint"] = np.array(joint, np.int32)
        if "displacement" in fields:
            h["faces/displacement"] = np.array(displacement, float)
        if "pressure" in fields:  # a water pressure rising face by face
            h["faces/pressure"] = 1000.0 * np.arange(len(fixed), dtype=float)


def run_dir(work, name, bodies_of_step, steps=(0, 10), **kw):
    d = os.path.join(work, name)
    os.makedirs(os.path.join(d, "snapshots"))
    for step in steps:
        write_snapshot(os.path.join(d, "snapshots", "snapshot_%010d.h5" % step),
                       bodies_of_step(step), step, **kw)
    return d


def slope(theta):
    """A fixed 45 deg slope 10 m high whose face looks towards azimuth theta, a free cube on it."""
    v, f = prism([(0, 0), (10, 0), (0, 10)], -5, 5)  # face x + z = 10 looks east and up
    cube_v, cube_f = box((3, -1, 7.1), (4, 0, 8.1))
    return [Body(rotated(v, theta), f, True),
            Body(rotated(cube_v, theta), cube_f, False, velocity=(0.5, 0, -0.5))]


def check_view(rf, work):
    for theta in (0.0, 90.0, -135.0, 30.0):
        d = run_dir(work, "slope_%g" % theta, lambda step, t=theta: slope(t))
        frames = [rf.Frame(p) for p in rf.pick(rf.snapshot_files(d), 4)]
        lo, hi = rf.view_box(frames)
        azimuth = rf.face_azimuth(frames[0], lo, hi)
        wanted = theta + rf.FACE_OFFSET
        error = (azimuth - wanted + 180.0) % 360.0 - 180.0
        print("slope facing %g deg: azimuth %.6f (expected %g)" % (theta, azimuth, wanted))
        expect(abs(error) < 1e-9, "slope facing %g deg: view azimuth %g, expected %g"
               % (theta, azimuth, wanted))
    # Rock masses of two free blocks side by side along x, the faces between them on joint 0.
    # A box-shaped mass (flat top, vertical sides) has no slope face; one whose face dips 60 deg
    # towards +y (azimuth 90) is seen from +y, whatever its joint faces.
    def mass(profile):
        def bodies(step):
            out = []
            for x0 in (0.0, 3.0):
                v, f = prism_x(profile, x0, x0 + 3.0)
                joints = [0 if np.all(v[face][:, 0] == 3.0) else -1 for face in f]
                out.append(Body(v, f, False, joints=joints))
            return out
        return bodies
    d = run_dir(work, "mass", mass([(0, 0), (6, 0), (6, 3), (0, 3)]), joint_names=("west",))
    frames = [rf.Frame(p) for p in rf.pick(rf.snapshot_files(d), 4)]
    lo, hi = rf.view_box(frames)
    direction = rf.face_direction(frames[0], lo, hi)
    expect(direction is None, "a box-shaped rock mass has no slope face, got %s" % direction)
    crest = 6.0 - 3.0 / math.tan(math.radians(60.0))
    d = run_dir(work, "slope_mass", mass([(0, 0), (6, 0), (crest, 3), (0, 3)]),
                joint_names=("west",))
    frames = [rf.Frame(p) for p in rf.pick(rf.snapshot_files(d), 4)]
    expect(int(np.sum(frames[0].joint == 0)) == 2, "the mass has two joint faces")
    lo, hi = rf.view_box(frames)
    azimuth = rf.face_azimuth(frames[0], lo, hi)
    print("rock mass with a face dipping towards +y: azimuth %.6f" % azimuth)
    expect(abs(azimuth - (90.0 + rf.FACE_OFFSET)) < 1e-9,
           "rock mass facing +y: azimuth %g, expected %g" % (azimuth, 90.0 + rf.FACE_OFFSET))
    # A cube on a flat floor: no face direction, the default view.
    floor_v, floor_f = box((-10, -10, -1), (10, 10, 0))
    cube_v, cube_f = box((0, 0, 0), (1, 1, 1))
    d = run_dir(work, "floor", lambda step: [Body(floor_v, floor_f, True),
                                             Body(cube_v, cube_f, False, velocity=(1, 0, 0))])
    frames = [rf.Frame(p) for p in rf.pick(rf.snapshot_files(d), 4)]
    lo, hi = rf.view_box(frames)
    expect(rf.face_azimuth(frames[0], lo, hi) == rf.DEFAULT_AZIMUTH, "a floor: default view")


def check_fields(rf, work):
    names = ("bedding", "north", "west")

    def bodies(step):
        out = slope(0.0)
        out[1].joints = [0, 2, -1, 2, -1, -1]
        return out
    d = run_dir(work, "fields", bodies, joint_names=names)
    for field in rf.FIELDS:
        png = os.path.join(work, "fields_%s.png" % field)
        out = rf.render(d, 2, png, field=field)
        with open(out, "rb") as f:
            expect(f.read(8) == b"\x89PNG\r\n\x1a\n", "%s: %s is not a PNG" % (field, out))
    frames = [rf.Frame(p, "joint") for p in rf.snapshot_files(d)]
    labels = [h.get_label() for h in rf.joint_legend(frames)]
    print("joint legend:", labels)
    expect(labels == ["no joint", "bedding", "west"], "joint legend %s" % labels)
    try:
        rf.render(d, 2, os.path.join(work, "x.png"), field="velocity")
        expect(False, "an unknown field was accepted")
    except ValueError as e:
        expect("velocity" in str(e) and "joint" in str(e), "unknown field message: %s" % e)
    bare = run_dir(work, "bare", bodies, fields=("fixed",))
    for field in ("displacement", "pressure", "joint"):
        try:
            rf.render(bare, 2, os.path.join(work, "y.png"), field=field)
            expect(False, "a missing field '%s' was accepted" % field)
        except KeyError as e:
            expect(field in str(e), "missing field message: %s" % e)


def main():
    script, work = sys.argv[1:3]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    rf = load(script)
    check_view(rf, work)
    check_fields(rf, work)
    if FAILURES:
        sys.exit("%d failure(s)" % len(FAILURES))
    print("all checks passed")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""The water pressure on the faces of a snapshot (field `pressure`, docs/output-files.md) against
the hydrostatic pressure computed here from the scene's [water] surface.

W-PLANAR-CRACK (its crack full of water) runs a few steps with snapshots. In the first snapshot,
on every face of a free block: a face on no joint carries 0; a face on a joint wholly below the
phreatic surface z_s(x, y) carries the mean of the linear pressure gamma_w (z_s - z) over it,
which is its value at the face's area centroid (computed here from /mesh), within 1e-9 of the
largest pressure; a face wholly above carries 0; a face the surface cuts carries a mean between
0 and the largest pressure on it. The base and the crack must be among the wet faces. The XDMF
collection names the attribute; a VTK run of the same scene carries it as cell data.

surface: W-PLANAR-CRACK-SURFACE, the same on its surface through seven points: over the free
block it is the plane through the points with x >= 0 (the crack's and the toe's).
drained: W-PLANAR-CRACK-DRAINED, the same, and the faces of the joints [[water.joint]] makes dry
carry 0 (only the crack is wet).

Usage: water_pressure_snapshot_test.py POLYDEM MODE SCENE WORKDIR (MODE: planar-crack, surface,
drained)
"""
import os
import tomllib

import h5py
import numpy as np

from scene_test_util import expect, main_by_mode, quantity, run


def surface(water, points=None):
    """z_s(x, y) of the scene's [water] (a level, or the plane through three points: those of
    [water], or the first three of `points` not on one line)."""
    if "level" in water:
        level = float(str(water["level"]).split()[0])
        return lambda x, y: level
    points = points or water["points"]
    (x0, y0, z0), (x1, y1, z1) = points[:2]
    (x2, y2, z2) = next(p for p in points[2:]
                        if (x1 - x0) * (p[1] - y0) - (y1 - y0) * (p[0] - x0) != 0)
    normal = np.cross([x1 - x0, y1 - y0, z1 - z0], [x2 - x0, y2 - y0, z2 - z0])
    return lambda x, y: z0 - (normal[0] * (x - x0) + normal[1] * (y - y0)) / normal[2]


def polygon_centroid(points):
    """Area centroid and area of a planar polygon (a fan of triangles from its first point)."""
    total, moment = 0.0, np.zeros(3)
    for a, b in zip(points[1:-1], points[2:]):
        area = 0.5 * np.linalg.norm(np.cross(a - points[0], b - points[0]))
        total += area
        moment += area * (points[0] + a + b) / 3
    return moment / total, total


def faces_of(path):
    """Per face: its points, fixed flag, joint and pressure."""
    with h5py.File(path) as h:
        points = h["mesh/points"][:]
        topology = h["mesh/topology"][:]
        fixed, joint, pressure = (h["faces/" + k][:] for k in ("fixed", "joint", "pressure"))
        unit = h["faces/pressure"].attrs.get("units")
    faces, i = [], 0
    while i < len(topology):
        n = int(topology[i + 1])
        faces.append(points[topology[i + 2:i + 2 + n]])
        i += 2 + n
    return faces, fixed, joint, pressure, unit


def check_planar_crack(polydem, scene_file, workdir, mode="planar-crack"):
    scene = tomllib.load(open(scene_file, "rb"))
    water = scene["water"]
    gamma = quantity(water.get("unit_weight", 9810.0), {"N/m^3": 1.0, "kN/m^3": 1e3})
    if mode == "surface":
        assert len(water["points"]) > 3
        z_s = surface(water, [p for p in water["points"] if p[0] >= 0])
    else:
        z_s = surface(water)
    names = [j["name"] for j in scene["joint"]]
    dry = {names.index(j["joint"]) for j in water.get("joint", []) if j.get("dry")}
    assert (mode == "drained") == bool(dry), "drained: some joint dry"
    run([polydem, "run", scene_file, "--out", "xdmf", "--steps", "2", "--quiet"], workdir)
    snapshots = sorted(os.listdir(os.path.join(workdir, "xdmf", "snapshots")))
    faces, fixed, joint, pressure, unit = faces_of(
        os.path.join(workdir, "xdmf", "snapshots", snapshots[0]))
    unit = unit.decode() if isinstance(unit, bytes) else unit
    expect(unit == "Pa", f"the pressure's units are {unit}, not Pa")
    wet = 0
    for k, points in enumerate(faces):
        head = np.array([z_s(x, y) - z for x, y, z in points])
        centroid, _ = polygon_centroid(points)
        expected = gamma * (z_s(centroid[0], centroid[1]) - centroid[2])
        peak = gamma * max(head.max(), 0.0)
        tol = 1e-9 * max(peak, 1.0)
        if fixed[k] or joint[k] < 0 or head.max() <= 0 or joint[k] in dry:
            expect(pressure[k] == 0.0, f"face {k} (fixed {fixed[k]}, joint {joint[k]}, highest "
                   f"head {head.max():.4g} m) carries {pressure[k]} Pa, expected 0")
        elif head.min() >= -1e-12:
            wet += 1
            print(f"face {k} on joint {joint[k]}: {pressure[k]:.6f} Pa, hydrostatic at its "
                  f"centroid depth {expected:.6f} Pa")
            expect(abs(pressure[k] - expected) <= tol,
                   f"face {k}: pressure {pressure[k]} Pa, hydrostatic {expected} Pa")
        else:
            expect(0.0 < pressure[k] < peak, f"face {k}, cut by the surface: {pressure[k]} Pa "
                   f"not between 0 and {peak} Pa")
    expected_wet = 1 if dry else 2
    expect(wet >= expected_wet, f"{wet} wholly wet joint faces, expected {expected_wet}")
    if dry:
        dry_faces = sum(1 for k in range(len(faces)) if not fixed[k] and joint[k] in dry)
        expect(dry_faces >= 1, "no face of the free block on the drained joint")

    with open(os.path.join(workdir, "xdmf", "snapshots.xmf")) as f:
        expect('Name="pressure"' in f.read(), "snapshots.xmf has no attribute 'pressure'")
    vtk_scene = os.path.join(workdir, "vtk.toml")
    with open(scene_file) as f, open(vtk_scene, "w") as out:
        out.write(f.read().replace("\n[water]\n",
                                  '\n[output]\nsnapshot_format = "vtk"\n\n[water]\n', 1))
    run([polydem, "run", vtk_scene, "--out", "vtk", "--steps", "2", "--quiet"], workdir)
    pieces = [p for p in os.listdir(os.path.join(workdir, "vtk", "snapshots"))
              if p.startswith("particles_") and p.endswith(".vtp")]
    with open(os.path.join(workdir, "vtk", "snapshots", sorted(pieces)[0])) as f:
        expect('Name="pressure"' in f.read(), "the VTK piece has no cell data 'pressure'")


if __name__ == "__main__":
    main_by_mode({"planar-crack": check_planar_crack,
                  "surface": lambda *a: check_planar_crack(*a, mode="surface"),
                  "drained": lambda *a: check_planar_crack(*a, mode="drained")})

#!/usr/bin/python3
"""Water in the joints ([water]) against the textbook answers, each computed from the scene file.

planar-crack SCENE: W-PLANAR-CRACK, `polydem fos` with the crack full (as written), half full and
  dry (the crack's two surface points lowered to z_w = z / 2 and 0): F within 2 % of Hoek and
  Bray's F = (c A + (W cos psi - U - V sin psi) tan phi) / (W sin psi + V cos psi), with
  U = gamma_w z_w A / 2 and V = gamma_w z_w^2 / 2 per metre of width.

wedge SCENE: W-WEDGE, `polydem fos`: F within 2 % of Hoek and Bray's vector method with the
  uplift forces U_A, U_B on the two planes. The wedge is cut here from the scene's box and planes
  (its vertices: the corners of the half-spaces); U_A, U_B are the pressure gamma_w (level - z)
  integrated over its faces on A and B, clipped at the level, triangle by triangle at the
  centroid (exact for a linear pressure), independently of polydem's integration.

surface SCENE: W-PLANAR-CRACK-SURFACE, `polydem fos`: the phreatic surface through more than three
  points, Hoek and Bray's plane over the block (level points on the crack x = 0, the rest on the
  plane through them and the toe) and any surface behind the crack (x < 0, over fixed rock): F
  within 2 % of Hoek and Bray's formula with the z_w of the crack's points.

drained SCENE: W-PLANAR-CRACK-DRAINED, `polydem fos`: Hoek and Bray's surface (three points) with
  the base joint dry ([[water.joint]] dry = true): F within 2 % of the formula with U = 0; and the
  same with no global surface and the crack alone given the level z_w ([[water.joint]]).

rising SCENE: W-RISING-WATER, `polydem run`: the water in the crack rises by the scene's table;
  the block must start to slide (move 1/1000 of its base's length) when the table's level is
  within 5 % of the z_w where Hoek and Bray's F(z_w) = 1 (solved by bisection).

Usage: water_scenes_test.py POLYDEM MODE SCENE WORKDIR
"""
import itertools
import csv
import math
import os
import re
import tomllib

import numpy as np
from scene_test_util import expect, fos, main_by_mode, normal_from_dip, quantity, run

# --- W-PLANAR-CRACK -------------------------------------------------------------------------
def planar_geometry(scene):
    """The planar slide of the scene: the base through the origin dipping east, the crack x = 0,
    the block east of it up to the region's top and its face x = x1."""
    mass = scene["rock_mass"][0]
    planes = {p["name"]: p for p in mass["plane"]}
    base, crack = planes["base"], planes["crack"]
    assert base["point"] == [0, 0, 0] and base["dip_direction"] == 90
    assert crack["point"] == [0, 0, 0] and crack["dip"] == 90 and crack["dip_direction"] == 90
    (_, y0, _), (x1, y1, z1) = mass["region"]["min"], mass["region"]["max"]
    psi = math.radians(base["dip"])
    joint = next(j for j in scene["joint"] if j["name"] == base["joint"])
    g = {"width": y1 - y0, "length": x1, "top": z1, "psi": psi,
         "phi": math.radians(joint["friction_angle"]),
         "cohesion": quantity(joint.get("cohesion", 0), {"kPa": 1e3, "Pa": 1.0, "MPa": 1e6}),
         "rho": quantity(scene["material"][0]["density"], {"kg/m^3": 1.0}),
         "gamma_w": quantity(scene["water"].get("unit_weight", 9810), {"N/m^3": 1.0, "kN/m^3": 1e3})}
    g["area"] = g["width"] * g["length"] / math.cos(psi)
    g["weight"] = g["rho"] * 9.81 * g["width"] * (g["length"] * z1 + g["length"]**2 * math.tan(psi) / 2)
    g["crack_depth"] = z1  # the base is at z = 0 under the crack
    g["toe"] = (x1, -x1 * math.tan(psi))
    return g


def hoek_bray(g, z_w, uplift=True):
    """Hoek and Bray's planar F with a water-filled tension crack (water to z_w above its foot),
    with the uplift on the base or (uplift False) the base drained."""
    u = g["gamma_w"] * z_w * g["area"] / 2 if uplift else 0.0
    v = g["gamma_w"] * z_w**2 / 2 * g["width"]
    w, psi = g["weight"], g["psi"]
    resisting = g["cohesion"] * g["area"] + (w * math.cos(psi) - u - v * math.sin(psi)) * math.tan(g["phi"])
    return resisting / (w * math.sin(psi) + v * math.cos(psi))


def crack_water_level(scene, g):
    """z_w of the scene's surface: two points on the crack (x = 0) at one height, one at the toe."""
    points = scene["water"]["points"]
    crack = [p for p in points if p[0] == 0]
    toe = [p for p in points if p[0] != 0]
    assert len(crack) == 2 and crack[0][2] == crack[1][2], "two points on the crack, level"
    assert len(toe) == 1 and toe[0][0] == g["toe"][0] and math.isclose(toe[0][2], g["toe"][1]), \
        "the third point is the toe"
    return crack[0][2]


def with_crack_level(text, z_w):
    """The scene text with the crack's two surface points at height z_w."""
    new, n = re.subn(r"\[0, (-?1), [-0-9.e]+\]", lambda m: f"[0, {m.group(1)}, {z_w!r}]", text)
    assert n == 2, "the two crack points of [water] points"
    return new


def check_planar_crack(polydem, scene_file, workdir):
    text = open(scene_file).read()
    scene = tomllib.loads(text)
    g = planar_geometry(scene)
    z = g["crack_depth"]
    assert crack_water_level(scene, g) == z, "the file has the crack full"
    for name, z_w in (("full", z), ("half", z / 2), ("dry", 0.0)):
        variant = os.path.join(workdir, f"crack-{name}.toml")
        with open(variant, "w") as f:
            f.write(with_crack_level(text, z_w))
        assert crack_water_level(tomllib.loads(open(variant).read()), g) == z_w
        expected = hoek_bray(g, z_w)
        f_measured = fos(polydem, variant, workdir, f"fos-{name}")
        error = abs(f_measured - expected) / expected
        print(f"crack {name} (z_w = {z_w} m): F = {f_measured}, expected {expected:.4f} "
              f"({error:.2%}, tolerance 2%)")
        expect(error <= 0.02, f"crack {name}: F = {f_measured}, expected {expected:.4f} within 2%")


def check_surface(polydem, scene_file, workdir):
    """The points: those on the crack (x = 0) at one level z_w, those over the block (x >= 0) on
    the plane through the crack's level and the toe, the others behind the crack."""
    scene = tomllib.load(open(scene_file, "rb"))
    g = planar_geometry(scene)
    points = scene["water"]["points"]
    assert len(points) > 3, "a surface through more than three points"
    crack = [p for p in points if p[0] == 0]
    assert len(crack) >= 2 and len({p[2] for p in crack}) == 1, "level points on the crack"
    assert {p[1] for p in crack} >= {-g["width"] / 2, g["width"] / 2}, "across the crack's width"
    z_w = crack[0][2]
    (x1, z1) = g["toe"]
    on_plane = lambda p: math.isclose(p[2], z_w + (z1 - z_w) * p[0] / x1, abs_tol=1e-12)
    front = [p for p in points if p[0] > 0]
    assert all(on_plane(p) for p in front), "Hoek and Bray's plane over the block"
    assert {(p[0], p[1]) for p in front} >= {(x1, -g["width"] / 2), (x1, g["width"] / 2)}, \
        "the surface covers the block up to its face"
    expected = hoek_bray(g, z_w)
    f_measured = fos(polydem, scene_file, workdir, "fos")
    error = abs(f_measured - expected) / expected
    print(f"surface of {len(points)} points (z_w = {z_w} m): F = {f_measured}, expected "
          f"{expected:.4f} ({error:.2%}, tolerance 2%)")
    expect(error <= 0.02, f"surface: F = {f_measured}, expected {expected:.4f} within 2%")


def crack_only(text, z_w):
    """The scene text with no global surface and the crack alone given the level z_w."""
    start, end = text.index("\npoints = "), text.index("[fos]")
    return text[:start] + f'\n\n[[water.joint]]\njoint = "crack"\nlevel = {z_w!r}\n\n' + text[end:]


def check_drained(polydem, scene_file, workdir):
    text = open(scene_file).read()
    scene = tomllib.loads(text)
    g = planar_geometry(scene)
    z_w = crack_water_level(scene, g)
    joints = scene["water"]["joint"]
    assert [(j["joint"], j.get("dry")) for j in joints] == [("base", True)], "the base drained"
    expected = hoek_bray(g, z_w, uplift=False)
    variant = os.path.join(workdir, "crack-only.toml")
    with open(variant, "w") as f:
        f.write(crack_only(text, z_w))
    water = tomllib.load(open(variant, "rb"))["water"]
    assert "points" not in water and water["joint"] == [{"joint": "crack", "level": z_w}]
    for name, scene_path in (("base drained", scene_file), ("crack alone", variant)):
        f_measured = fos(polydem, scene_path, workdir, "fos-" + name.replace(" ", "-"))
        error = abs(f_measured - expected) / expected
        print(f"{name} (z_w = {z_w} m, U = 0): F = {f_measured}, expected {expected:.4f} "
              f"({error:.2%}, tolerance 2%)")
        expect(error <= 0.02, f"{name}: F = {f_measured}, expected {expected:.4f} within 2%")


# --- W-RISING-WATER ---------------------------------------------------------------------------
def level_of_failure(g):
    """The z_w in [0, crack depth] where F(z_w) = 1, by bisection; F falls as z_w rises."""
    lo, hi = 0.0, g["crack_depth"]
    assert hoek_bray(g, lo) > 1 > hoek_bray(g, hi), "stable dry, failed with the crack full"
    for _ in range(60):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if hoek_bray(g, mid) > 1 else (lo, mid)
    return (lo + hi) / 2


def table_level(scene, g, time):
    """The crack's water level of the scene's table at `time` (rows [t, z1, z2, z3]; the points
    on the crack first, the toe last), linear between rows."""
    water = scene["water"]
    assert [p[0] for p in water["points"]] == [0, 0, g["toe"][0]], "crack, crack, toe"
    rows = water["table"]
    assert all(math.isclose(r[3], g["toe"][1]) and r[1] == r[2] for r in rows)
    if time <= rows[0][0]:
        return rows[0][1]
    for a, b in zip(rows, rows[1:]):
        if time <= b[0]:
            return a[1] + (time - a[0]) / (b[0] - a[0]) * (b[1] - a[1])
    return rows[-1][1]


def check_rising(polydem, scene_file, workdir):
    scene = tomllib.load(open(scene_file, "rb"))
    g = planar_geometry(scene)
    expected = level_of_failure(g)
    run([polydem, "run", scene_file, "--out", "run", "--quiet", "--no-snapshots"], workdir)
    label = scene["output"]["monitor"][0]
    with open(os.path.join(workdir, "run", "series.csv")) as f:
        rows = list(csv.DictReader(f))
    position = lambda r: np.array([float(r[f"{label}_{c}"]) for c in "xyz"])
    start = position(rows[0])
    threshold = 1e-3 * g["length"] / math.cos(g["psi"])  # of the base's length
    moved = [r for r in rows if np.linalg.norm(position(r) - start) > threshold]
    expect(moved, f"the block never moved {threshold} m")
    if not moved:
        return
    t = float(moved[0]["time"])
    level = table_level(scene, g, t)
    error = abs(level - expected) / expected
    print(f"rising: the block moved {threshold:.4f} m at t = {t} s, water level {level:.4f} m; "
          f"F = 1 at {expected:.4f} m ({error:.2%}, tolerance 5%)")
    expect(error <= 0.05, f"rising: slid at level {level:.4f} m, F = 1 at {expected:.4f} m")


# --- W-WEDGE --------------------------------------------------------------------------------
def convex_cell(halfspaces):
    """Vertices of {x : n . x <= d for every (n, d)}: the feasible corners of three planes."""
    vertices = []
    for planes in itertools.combinations(halfspaces, 3):
        m = np.array([n for n, _ in planes])
        if abs(np.linalg.det(m)) < 1e-12:
            continue
        x = np.linalg.solve(m, [d for _, d in planes])
        if all(n @ x <= d + 1e-9 for n, d in halfspaces) and \
                not any(np.linalg.norm(x - v) < 1e-9 for v in vertices):
            vertices.append(x)
    return np.array(vertices)


def face_polygon(vertices, n, d):
    """The vertices on the plane n . x = d (n unit), counter-clockwise about n."""
    on = [v for v in vertices if abs(n @ v - d) < 1e-9]
    c = np.mean(on, axis=0)
    u = (on[0] - c) / np.linalg.norm(on[0] - c)
    w = np.cross(n, u)
    return sorted(on, key=lambda v: math.atan2((v - c) @ w, (v - c) @ u))


def triangle_area(a, b, c):
    return 0.5 * np.linalg.norm(np.cross(b - a, c - a))


def polyhedron_volume(vertices, halfspaces):
    """Sum over the faces of the pyramids from the vertices' mean."""
    c = vertices.mean(axis=0)
    volume = 0.0
    for n, d in halfspaces:
        if sum(abs(n @ v - d) < 1e-9 for v in vertices) < 3:
            continue
        f = face_polygon(vertices, n, d)
        area = sum(triangle_area(f[0], f[k], f[k + 1]) for k in range(1, len(f) - 1))
        volume += area * (d - n @ c) / 3
    return volume


def water_force(polygon, level, gamma_w):
    """The integral of gamma_w (level - z) over the part of `polygon` below the level."""
    wet = []
    for a, b in zip(polygon, polygon[1:] + polygon[:1]):
        pa, pb = level - a[2], level - b[2]
        if pa >= 0:
            wet.append(a)
        if (pa >= 0) != (pb >= 0):
            wet.append(a + pa / (pa - pb) * (b - a))
    total = 0.0
    for k in range(1, len(wet) - 1):
        centroid = (wet[0] + wet[k] + wet[k + 1]) / 3
        total += triangle_area(wet[0], wet[k], wet[k + 1]) * gamma_w * (level - centroid[2])
    return total


def vector_method_with_water(scene):
    mass = scene["rock_mass"][0]
    friction = {j["name"]: math.radians(j["friction_angle"]) for j in scene["joint"]}
    lo, hi = np.array(mass["region"]["min"], float), np.array(mass["region"]["max"], float)
    box = [(e, hi @ e) for e in np.eye(3)] + [(-e, -(lo @ e)) for e in np.eye(3)]
    a, b = mass["plane"]
    assert a["fixed"] == b["fixed"] == "below", "the wedge is above both planes"
    normals = [normal_from_dip(p["dip"], p["dip_direction"]) for p in (a, b)]
    joints = [(-n, -(n @ np.array(p["point"], float))) for n, p in zip(normals, (a, b))]
    wedge = convex_cell(box + joints)
    volume = polyhedron_volume(wedge, box + joints)
    weight = np.array([0.0, 0.0, -quantity(scene["material"][0]["density"], {"kg/m^3": 1.0})
                       * 9.81 * volume])
    water = scene["water"]
    level = quantity(water["level"], {"m": 1.0})
    gamma_w = quantity(water.get("unit_weight", 9810), {"N/m^3": 1.0, "kN/m^3": 1e3})
    uplift = [water_force(face_polygon(wedge, n, d), level, gamma_w) for n, d in joints]
    i = np.cross(*normals)
    i /= np.linalg.norm(i)
    if i[2] > 0:
        i = -i  # down the line of intersection
    # The water pushes the wedge off each plane, along its upward normal.
    active = weight + uplift[0] * normals[0] + uplift[1] * normals[1]
    n_a, n_b, _ = np.linalg.solve(np.column_stack([normals[0], normals[1], i]), -active)
    assert n_a > 0 and n_b > 0, "the wedge must rest on both planes"
    f = (n_a * math.tan(friction[a["joint"]]) + n_b * math.tan(friction[b["joint"]])) / (weight @ i)
    print(f"wedge: volume {volume:.4f} m^3, W = {-weight[2]:.0f} N, U_A = {uplift[0]:.0f} N, "
          f"U_B = {uplift[1]:.0f} N, N_A = {n_a:.0f} N, N_B = {n_b:.0f} N")
    return f


def check_wedge(polydem, scene_file, workdir):
    expected = vector_method_with_water(tomllib.load(open(scene_file, "rb")))
    f_measured = fos(polydem, scene_file, workdir, "fos")
    error = abs(f_measured - expected) / expected
    print(f"wedge: F = {f_measured}, expected {expected:.4f} ({error:.2%}, tolerance 2%)")
    expect(error <= 0.02, f"wedge: F = {f_measured}, expected {expected:.4f} within 2%")


if __name__ == "__main__":
    main_by_mode({"planar-crack": check_planar_crack, "wedge": check_wedge, "rising": check_rising,
                  "surface": check_surface, "drained": check_drained})

#!/usr/bin/python3
"""Water in the joints ([water]) against the textbook answers, each computed from the scene file.

planar-crack SCENE: W-PLANAR-CRACK, `polydem fos` with the crack full (as written), half full and
  dry (the crack's two surface points lowered to z_w = z / 2 and 0): F within 2 % of Hoek and
  Bray's F = (c A + (W cos psi - U - V sin psi) tan phi) / (W sin psi + V cos psi), with
  U = gamma_w z_w A / 2 and V = gamma_w z_w^2 / 2 per metre of width.

Usage: water_scenes_test.py POLYDEM MODE SCENE WORKDIR
"""
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tomllib

FAILURES = []


def expect(ok, message):
    if not ok:
        FAILURES.append(message)
        print("FAIL:", message)


def run(cmd, workdir):
    out = subprocess.run(cmd, cwd=workdir, capture_output=True, text=True)
    if out.returncode != 0:
        print(out.stdout[-3000:], out.stderr[-3000:])
        sys.exit(f"{cmd[:2]} failed with exit status {out.returncode}")
    return out


def quantity(text, units):
    """'10 kPa' -> 10000.0 with units {'kPa': 1e3, ...}; a plain number as it is."""
    if isinstance(text, (int, float)):
        return float(text)
    number, unit = text.split()
    return float(number) * units[unit]


def fos(polydem, scene, workdir, out):
    run([polydem, "fos", scene, "--out", out, "--quiet"], workdir)
    with open(os.path.join(workdir, out, "fos.json")) as f:
        return json.load(f)["factor_of_safety"]


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


def hoek_bray(g, z_w):
    """Hoek and Bray's planar F with a water-filled tension crack (water to z_w above its foot)."""
    u = g["gamma_w"] * z_w * g["area"] / 2
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


def main():
    polydem, mode, scene, workdir = sys.argv[1:5]
    polydem = os.path.abspath(polydem)
    scene = os.path.abspath(scene)
    workdir = os.path.abspath(workdir)
    shutil.rmtree(workdir, ignore_errors=True)
    os.makedirs(workdir)
    {"planar-crack": check_planar_crack}[mode](polydem, scene, workdir)
    if FAILURES:
        sys.exit(f"{len(FAILURES)} failure(s)")
    print("all checks passed")


if __name__ == "__main__":
    main()

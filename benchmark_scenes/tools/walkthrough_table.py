#!/usr/bin/env python3
"""The factor of safety of one planar slide (J-PLANAR-COHESION's geometry: a 6 x 2 x 3 m box of
rock cut by a base joint dipping psi east and a vertical tension crack at x = 0, the block east of
the crack free) dry, with water in the crack, under a pseudo-static earthquake, bolted, and all
three at once: `polydem fos` beside Hoek and Bray's limit equilibrium (Rock Slope Engineering,
ch. 6), each formula computed from the scene file's own inputs:

  F = (c A + (W cos psi - U - V sin psi - kh W sin psi + T cos beta) tan phi)
      / (W sin psi + V cos psi + kh W cos psi - T sin beta),

A the base area, W the block's weight, U = gamma_w z_w A / 2 the uplift on the base and
V = gamma_w z_w^2 / 2 x width the water force in the crack (z_w: the water's height in the crack,
the phreatic plane falling linearly to the toe; a plane drained by [[water.joint]] dry = true
carries none), kh the horizontal seismic coefficient (out of the slope), T a bolt's yield force
at beta from the base's inward normal (up-dip).

  /usr/bin/python3 benchmark_scenes/tools/walkthrough_table.py --polydem build/bin/polydem

prints a Markdown table (README's walkthrough) and exits non-zero when a case is more than 2 %
from its formula.
"""

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import tomllib

HERE = os.path.dirname(os.path.abspath(__file__))
SCENES = os.path.dirname(HERE)

CASES = [
    ("dry", "J-PLANAR-COHESION.toml"),
    ("tension crack full of water", "W-PLANAR-CRACK.toml"),
    ("crack full, base drained", "W-PLANAR-CRACK-DRAINED.toml"),
    ("crack full, earthquake kh = 0.1", "examples/planar-wet-shaken.toml"),
    ("dry, one bolt (50 kN)", "examples/planar-bolted.toml"),
    ("crack full, kh = 0.1, one bolt", "examples/planar-wet-shaken-bolted.toml"),
]

SI = {"Pa": 1.0, "kPa": 1e3, "MPa": 1e6, "N": 1.0, "kN": 1e3, "MN": 1e6, "kg/m^3": 1.0,
      "N/m^3": 1.0, "kN/m^3": 1e3, "m": 1.0, "m/s^2": 1.0}


def si(value):
    """'10 kPa' -> 10000.0; a plain number as it is."""
    if isinstance(value, (int, float)):
        return float(value)
    number, unit = value.split()
    return float(number) * SI[unit]


def by_name(items, name):
    return next(item for item in items if item["name"] == name)


def limit_equilibrium(scene):
    """Hoek and Bray's F for the planar slide the scene describes."""
    mass = scene["rock_mass"][0]
    lo, hi = mass["region"]["min"], mass["region"]["max"]
    psi = math.radians(by_name(mass["plane"], "base")["dip"])
    length, width, top = hi[0], hi[1] - lo[1], hi[2]  # crack at x = 0, base through the origin
    volume = width * (top * length + length**2 * math.tan(psi) / 2)
    weight = si(scene["material"][0]["density"]) * 9.81 * volume
    area = width * length / math.cos(psi)
    base = by_name(scene["joint"], "base")
    phi, cohesion = math.radians(base["friction_angle"]), si(base.get("cohesion", 0))
    uplift = crack = 0.0
    if "water" in scene:
        gamma = si(scene["water"]["unit_weight"])
        z_w = max(p[2] for p in scene["water"]["points"] if p[0] == 0)
        uplift, crack = gamma * z_w * area / 2, gamma * z_w**2 / 2 * width
        dry = {j["joint"] for j in scene["water"].get("joint", []) if j.get("dry", False)}
        uplift = 0.0 if "base" in dry else uplift  # [[water.joint]] dry = true drains a plane
        crack = 0.0 if "crack" in dry else crack
    kh = scene.get("seismic", {}).get("kh", 0.0)
    pull = beta = 0.0
    if "bolt" in scene:
        bolt = scene["bolt"][0]
        pull = si(bolt["axial_yield"])
        t, p = math.radians(bolt["trend"]), math.radians(bolt["plunge"])
        axis = (math.cos(p) * math.sin(t), math.cos(p) * math.cos(t), -math.sin(p))
        inward = (-math.sin(psi), 0.0, -math.cos(psi))  # into the base, the slide dipping east
        down_dip = (math.cos(psi), 0.0, -math.sin(psi))
        beta = math.acos(sum(a * b for a, b in zip(axis, inward)))
        if sum(a * b for a, b in zip(axis, down_dip)) > 0:
            beta = -beta  # a bolt pulling down-dip drives the slide
    normal = weight * math.cos(psi) - uplift - crack * math.sin(psi) - kh * weight * math.sin(psi)
    normal += pull * math.cos(beta)
    driving = weight * math.sin(psi) + crack * math.cos(psi) + kh * weight * math.cos(psi)
    driving -= pull * math.sin(beta)
    return (cohesion * area + normal * math.tan(phi)) / driving


def polydem_fos(polydem, scene, ranks):
    with tempfile.TemporaryDirectory() as work:
        out = os.path.join(work, "fos")
        cmd = ["mpirun", "-n", str(ranks), polydem, "fos", scene, "--out", out, "--quiet"]
        env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                   OMPI_MCA_btl_vader_single_copy_mechanism="none")
        subprocess.run(cmd, check=True, env=env, capture_output=True)
        with open(os.path.join(out, "fos.json")) as f:
            return json.load(f)["factor_of_safety"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--polydem", default="build/bin/polydem")
    parser.add_argument("--ranks", type=int, default=2)
    args = parser.parse_args()
    print("| case | scene | F, polydem fos | F, limit equilibrium | difference |")
    print("|---|---|---|---|---|")
    worst = 0.0
    for case, name in CASES:
        path = os.path.join(SCENES, name)
        with open(path, "rb") as f:
            expected = limit_equilibrium(tomllib.load(f))
        got = polydem_fos(os.path.abspath(args.polydem), path, args.ranks)
        diff = (got - expected) / expected
        worst = max(worst, abs(diff))
        print(f"| {case} | `benchmark_scenes/{name}` | {got:.4f} | {expected:.4f} | {100 * diff:+.2f} % |",
              flush=True)
    sys.exit(1 if worst > 0.02 else 0)


if __name__ == "__main__":
    main()

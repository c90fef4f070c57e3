#!/usr/bin/env python3
"""Writes F-TOPPLING-SET.toml: Goodman and Bray's (1976) block-toppling set, columns of width dx
and rising, then falling heights standing on a stepped base whose treads dip psi_p.

Frame: x horizontal, pointing down the dip, z up. The base frame is x' = (cos psi, 0, -sin psi)
(down the treads) and z' = (sin psi, 0, cos psi) (their normal); every column and step is a box
with its edges along x', y and z', turned by psi about y. Column i (i = 1 at the toe) stands on
tread i, whose top is (i - 1) b above the toe's along z', and spans x' in
[-(i - 1/2) dx, -(i - 3/2) dx]. The steps are fixed, the columns free; one friction angle for
every contact. tests/apps/fos_toppling_set_test.py reads the columns back from the scene file and
computes the limit friction angle with Goodman and Bray's recursion.
"""
import math
import os

PSI = 20.0                                  # deg: dip of the treads (the columns' bases)
DX = 1.0                                    # m: column width along the dip
WIDTH = 1.0                                 # m: along strike
STEP = 0.25                                 # m: rise of each tread over the next lower one (b)
HEIGHTS = [1.0, 2.0, 3.0, 4.0, 3.0, 2.0, 1.0]  # m: from the toe up
TREAD = 1.0                                 # m: thickness of a step below its tread
PHI = 45.0                                  # deg: the scene's friction angle


def vec(v):
    return "[" + ", ".join(f"{x:.12g}" for x in v) + "]"


def world(xp, zp):
    s, c = math.sin(math.radians(PSI)), math.cos(math.radians(PSI))
    return (xp * c + zp * s, 0.0, -xp * s + zp * c)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    n = len(HEIGHTS)
    out = [
        "# F-TOPPLING-SET (BENCHMARKS.md section F): Goodman and Bray's (1976) block toppling. Seven",
        f"# columns {DX:g} m wide (dx) and {WIDTH:g} m deep, {', '.join(f'{h:g}' for h in HEIGHTS)} m tall from the toe",
        f"# up, stand on a staircase of fixed steps whose treads dip psi_p = {PSI:g} deg, each tread",
        f"# {STEP:g} m above the next lower one (measured normal to the treads); the columns' sides",
        f"# are normal to the treads. One friction angle, {PHI:g} deg, for every contact.",
        "#",
        "# Analytical answer: the friction angle phi* at which Goodman and Bray's recursion needs no",
        "# force at the toe (P_0 = 0). From the crest down, block n passes to the block below it",
        "#   toppling: P_{n-1,t} = [P_n (M_n - dx tan phi) + W_n / 2 (y_n sin psi_p - dx cos psi_p)] / L_n",
        "#   sliding:  P_{n-1,s} = P_n - W_n (tan phi cos psi_p - sin psi_p) / (1 - tan^2 phi)",
        "# and the larger of the two (0 when both are negative: the block stands alone); M_n and L_n",
        "# are the heights above block n's base of the top of its contact with the block above and",
        "# below (the shorter face of the pair, the steps counted). For this set phi* = "
        "{phi_star} deg",
        "# (toppling of the middle columns). `polydem fos` with its default criterion must give",
        "# atan(tan(phi) / F) within 2 deg of phi* (ctest apps_fos_toppling_set, which computes phi*",
        "# from the columns in this file).",
        "#",
        "#   polydem fos benchmark_scenes/F-TOPPLING-SET.toml --out results/fos-toppling-set",
        "#",
        "# Written by tools/make_toppling_set.py; edit that, not this.",
        "",
        "[scene]", 'id = "F-TOPPLING-SET"',
        'title = "Goodman and Bray block toppling on a stepped base: the limit friction by polydem fos"',
        'source = "Goodman and Bray (1976); Hoek and Bray, Rock Slope Engineering, ch. 10; '
        'BENCHMARKS.md F-TOPPLING-SET"', "",
        "[simulation]", 'kernel = "gjk-epa-ipm"', 'dt = "1e-4 s"', 'end_time = "2 s"', "",
        "[[material]]", 'name = "rock"', 'density = "2650 kg/m^3"', 'kn = "1 GN/m"',
        'ks = "0.5 GN/m"', f"friction_angle = {PHI:g}", "",
        f"# psi_p = {PSI:g} deg, dx = {DX:g} m, b = {STEP:g} m (the test reads them back from the boxes below)",
    ]
    rot = f"rotation = {{ axis = [0, 1, 0], angle = {PSI:g} }}"
    out += ["[[shape]]", 'name = "step"', 'type = "box"', f"size = {vec((DX, WIDTH, TREAD))}", rot, ""]
    for i, h in enumerate(HEIGHTS, start=1):
        out += ["[[shape]]", f'name = "column{i}"', 'type = "box"', f"size = {vec((DX, WIDTH, h))}",
                rot, ""]
    for i, h in enumerate(HEIGHTS, start=1):
        xp = -(i - 1) * DX
        base = (i - 1) * STEP
        out += ["[[particle]]", f'label = "step_{i}"', 'shape = "step"', 'material = "rock"',
                "fixed = true", f"position = {vec(world(xp, base - 0.5 * TREAD))}", ""]
        out += ["[[particle]]", f'label = "column_{i}"', f'shape = "column{i}"', 'material = "rock"',
                f"position = {vec(world(xp, base + 0.5 * h))}", ""]
    out += ["[fos]                # the default criterion; the range, resolution and trial length only",
            'label_prefix = "column"', "f_min = 0.5", "f_max = 3", "resolution = 0.01",
            'max_time = "2 s"', ""]
    text = "\n".join(out)
    import importlib.util
    spec = importlib.util.spec_from_file_location(
        "gb", os.path.join(here, "..", "..", "tests", "apps", "goodman_bray.py"))
    gb = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gb)
    zb = [(i * STEP) for i in range(n)]
    phi_star, _ = gb.limit_friction(PSI, DX, HEIGHTS, zb)
    text = text.replace("{phi_star}", f"{phi_star:.2f}")
    with open(os.path.join(here, "..", "F-TOPPLING-SET.toml"), "w") as f:
        f.write(text)


if __name__ == "__main__":
    main()

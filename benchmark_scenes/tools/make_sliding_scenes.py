#!/usr/bin/env python3
"""Writes D-SLIDING-BLOCK.toml and D-SLIDING-BLOCK-KN.toml (Zhao section 5.2, eqs. 41-42).

A 1 x 1 x 0.5 m cuboid is launched at 6 m/s up a 30 deg incline. Each scene holds three blocks on
three inclines side by side (5 m apart): friction mu = 0.2, 0.4, 0.6 in the first scene; mu = 0.4
and kn = 1.5e7, 1.5e8, 1.5e9 N/m in the second. Blocks start at their static penetration so that
the normal spring is not excited."""
import math

THETA = 30.0
G = 9.81
DENSITY = 2500.0
SIZE = (1.0, 1.0, 0.5)
KS = 1.2e8
U0 = 6.0
t = math.radians(THETA)
n = (-math.sin(t), 0.0, math.cos(t))  # incline normal (rotation about y by -theta)
d = (math.cos(t), 0.0, math.sin(t))   # up the slope
mass = DENSITY * SIZE[0] * SIZE[1] * SIZE[2]
normal_force = mass * G * math.cos(t)


def vec(v):
    return "[" + ", ".join(f"{x:.12g}" for x in v) + "]"


def penalty(kn):
    """The distance potential's penalty (Pa) with the block's stiffness kn on its base: a depth d
    gives the force penalty * area * d / inradius (Zhao eqs. 5, 13)."""
    return kn * (min(SIZE) / 2) / (SIZE[0] * SIZE[1])


def scene(ident, title, variants, note):
    out = [f"# {ident}: {title}.", "#", "# Written by tools/make_sliding_scenes.py; edit that, not this.",
           "# " + note, "", "[scene]", f'id = "{ident}"', f'title = "{title}"',
           'source = "Zhao section 5.2, table 1, eqs. 41-42; BENCHMARKS.md D-SLIDING-BLOCK"', "",
           "[simulation]", 'kernel = "fcp-ipm"', 'dt = "5e-5 s"', 'end_time = "2 s"', "",
           "[domain]", "min = [-8, -4, -5]", "max = [8, 14, 6]", ""]
    labels = []
    for i, (mu, kn) in enumerate(variants):
        tag = f"{i}"
        out += ["[[material]]", f'name = "block{tag}"', f"density = {DENSITY}", f"kn = {kn:g}",
                f"penalty = {penalty(kn):g}", f"ks = {KS:g}", "friction_angle = 0", "",
                "[[material]]", f'name = "incline{tag}"', f"density = {DENSITY}", f"kn = {kn:g}",
                f"penalty = {penalty(kn):g}", f"ks = {KS:g}", "friction_angle = 0", "",
                "[[interaction]]", f'materials = ["block{tag}", "incline{tag}"]', f"kn = {kn:g}",
                f"penalty = {penalty(kn):g}   # distance-potential: kn x inradius / base area",
                f"ks = {KS:g}", f"friction_angle = {math.degrees(math.atan(mu)):.12g}   # mu = {mu}", ""]
    out += ["[[shape]]", 'name = "block"', 'type = "box"', f"size = {vec(SIZE)}",
            f"rotation = {{ axis = [0, 1, 0], angle = {-THETA} }}", "",
            "[[shape]]", 'name = "incline"', 'type = "box"', "size = [12, 3, 1]",
            f"rotation = {{ axis = [0, 1, 0], angle = {-THETA} }}", ""]
    for i, (mu, kn) in enumerate(variants):
        y = 5.0 * i
        delta = normal_force / kn
        h = SIZE[2] / 2 - delta
        centre = tuple(h * n[k] for k in range(3))
        centre = (centre[0], y, centre[2])
        out += ["[[particle]]", 'shape = "incline"', f'material = "incline{i}"', "fixed = true",
                f"position = {vec((-0.5 * n[0], y, -0.5 * n[2]))}", "",
                "[[particle]]", f'label = "block{i}"', 'shape = "block"', f'material = "block{i}"',
                f"position = {vec(centre)}   # static penetration m g cos(theta) / kn = {delta:.6g} m",
                f"velocity = {vec(tuple(U0 * c for c in d))}   # {U0} m/s up the slope", ""]
        labels.append(f"block{i}")
    out += ["[output]", "series_every = 100", f"monitor = {labels}".replace("'", '"'), ""]
    for i, (mu, kn) in enumerate(variants):
        for q in ("displacement", "velocity"):
            out += ["[[check]]", f'name = "block{i} {q} (mu {mu}, kn {kn:g})"', 'kind = "sliding_block"',
                    f'particle = "block{i}"', f'quantity = "{q}"', f"theta = {THETA}", f"mu = {mu}",
                    f"u0 = {U0}", f"direction = {vec(d)}", "expected = 0.01", 'compare = "max"',
                    'reference = "Zhao eqs. 41-42; BENCHMARKS.md: relative error < 1 %"', ""]
    return "\n".join(out)


with open("D-SLIDING-BLOCK.toml", "w") as f:
    f.write(scene("D-SLIDING-BLOCK", "Block launched up a 30 degree incline, three friction coefficients",
                  [(0.2, 1.5e8), (0.4, 1.5e8), (0.6, 1.5e8)],
                  "mu = 0.2 and 0.4 slide back down (tan 30 > mu); mu = 0.6 stops and stays."))
with open("D-SLIDING-BLOCK-KN.toml", "w") as f:
    f.write(scene("D-SLIDING-BLOCK-KN", "Block launched up a 30 degree incline, three normal stiffnesses",
                  [(0.4, 1.5e7), (0.4, 1.5e8), (0.4, 1.5e9)],
                  "Zhao fig. 31: the result must not depend on the normal penalty kn."))

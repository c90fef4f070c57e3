#!/usr/bin/env python3
"""Writes D-WEDGE-SLIDE.toml (Zhao section 5.6, eq. 45) and S-WEDGE-32.toml (Keissar fig. 2.11)."""
import math


def vec(v):
    return "[" + ", ".join(f"{x:.12g}" for x in v) + "]"


def prism(section, x0, x1):
    """Vertices of the prism with cross-section `section` [(y, z), ...] between x0 and x1."""
    return [(x, y, z) for x in (x0, x1) for (y, z) in section]


def vertices(pts):
    return "vertices = [" + ", ".join(vec(p) for p in pts) + "]"


def wedge_slide():
    out = ["# D-WEDGE-SLIDE (Zhao section 5.6, eq. 45): a frictionless wedge in a V-shaped groove whose",
           "# trough line dips theta = 20, 30 and 40 deg. Normal forces act across the line, so the",
           "# wedge slides along it with s = g t^2 sin(theta) / 2 whatever the groove's opening.",
           "# Three grooves side by side, 8 m apart. The walls are at 45 deg to the vertical; the wedge",
           "# is a trapezoidal prism whose two lower faces lie on the walls.",
           "#", "# Written by tools/make_wedge_scenes.py; edit that, not this.", "",
           "[scene]", 'id = "D-WEDGE-SLIDE"', 'title = "Frictionless wedge sliding down a V-groove"',
           'source = "Zhao section 5.6, table 8, eq. 45; BENCHMARKS.md D-WEDGE-SLIDE"', "",
           "[simulation]", 'kernel = "fcp-ipm"', 'dt = "1e-4 s"', 'end_time = "1 s"', "",
           "[domain]", "min = [-8, -6, -6]", "max = [8, 22, 6]", "",
           "[[material]]", 'name = "rock"', 'density = "2600 kg/m^3"', 'kn = "2 GN/m"',
           'penalty = "0.6 GPa"   # distance-potential: about kn x inradius / contact area',
           'ks = "0.12 GN/m"', "friction_angle = 0", "normal_damping = 0.2", ""]
    left = [(0, 0), (-3, 3), (-3 - math.sqrt(0.5), 3 - math.sqrt(0.5)), (-math.sqrt(0.5), -math.sqrt(0.5))]
    right = [(-y, z) for (y, z) in left]
    wedge = [(-0.1, 0.1), (0.1, 0.1), (1.0, 1.0), (-1.0, 1.0)]
    thetas = (20, 30, 40)
    for theta in thetas:
        rot = f"rotation = {{ axis = [0, 1, 0], angle = {theta} }}   # local +x dips {theta} deg"
        for name, sec, x0, x1 in (("left", left, -6, 6), ("right", right, -6, 6), ("wedge", wedge, -5.5, -3.5)):
            out += ["[[shape]]", f'name = "{name}{theta}"', 'type = "vertices"',
                    vertices(prism(sec, x0, x1)), rot, ""]
    for i, theta in enumerate(thetas):
        y = 8.0 * i
        for wall in ("left", "right"):
            out += ["[[particle]]", f'shape = "{wall}{theta}"', 'material = "rock"', "fixed = true",
                    f"position = [0, {y}, 0]", ""]
        out += ["[[particle]]", f'label = "wedge{theta}"', f'shape = "wedge{theta}"', 'material = "rock"',
                f"position = [0, {y}, 0]", ""]
    out += ["[output]", "series_every = 100", 'monitor = ["wedge20", "wedge30", "wedge40"]', ""]
    for theta in thetas:
        t = math.radians(theta)
        out += ["[[check]]", f'name = "wedge {theta} deg"', 'kind = "wedge_slide"', f'particle = "wedge{theta}"',
                f"theta = {theta}", f"direction = {vec((math.cos(t), 0, -math.sin(t)))}", "expected = 0.01",
                'compare = "max"', 'reference = "Zhao eq. 45; BENCHMARKS.md: relative error < 1 %"', ""]
    return "\n".join(out)


def wedge_32():
    slope = 20.0
    s = math.tan(math.radians(slope))
    h0 = 0.5
    xs = [0.0, 1.0, 2.0, 3.0, 4.0]                 # 4 slices along the dip
    ys = [0.5 * j for j in range(9)]               # 8 slices along the strike
    out = ["# S-WEDGE-32 (Keissar section 2.4, fig. 2.11, table 2.1): a rock wedge on a 20 deg slope, cut",
           "# by vertical joints into 4 x 8 = 32 prisms. Friction 25 deg on the base and the joints holds",
           "# every block (tan 25 > tan 20); the blocks are too squat to topple. With GJK-EPA's",
           "# off-centre contact points some blocks turn and push their neighbours down the slope",
           "# (fig. 2.11b); with IPM they stay (fig. 2.11d).",
           "# The slope surface is the plane z = -x tan(20 deg); the mass lies between it and z = 0.5 m.",
           "#", "# Written by tools/make_wedge_scenes.py; edit that, not this.", "",
           "[scene]", 'id = "S-WEDGE-32"', 'title = "Jointed wedge of 32 prisms on a 20 degree slope"',
           'source = "Keissar fig. 2.11, table 2.1; BENCHMARKS.md S-WEDGE-32"', "",
           "[simulation]", 'kernel = "gjk-epa-ipm"', 'dt = "1e-4 s"', 'end_time = "3 s"', "",
           "[domain]", "min = [-3, -2, -5]", "max = [7, 6.5, 3]", "",
           "[[material]]", 'name = "rock"', 'density = "2000 kg/m^3"', 'kn = "10 GN/m"',
           'penalty = "3 GPa"   # distance-potential: about kn x inradius / contact area', 'ks = "5 GN/m"',
           "friction_angle = 25", "local_damping = 0.05", "",
           "[[shape]]", 'name = "slope"', 'type = "box"', "size = [12, 10, 2]",
           f"rotation = {{ axis = [0, 1, 0], angle = {slope} }}", "",
           "[[particle]]", 'label = "slope"', 'shape = "slope"', 'material = "rock"', "fixed = true"]
    t = math.radians(slope)
    n = (math.sin(t), 0.0, math.cos(t))
    centre = (2.0 - 1.0 * n[0], 2.0, -2.0 * s - 1.0 * n[2])  # top face through (2, y, -2 tan 20)
    out += [f"position = {vec(centre)}", ""]
    k = 0
    for i in range(4):
        for j in range(8):
            x0, x1, y0, y1 = xs[i], xs[i + 1], ys[j], ys[j + 1]
            pts = [(x, y, z) for x in (x0, x1) for y in (y0, y1) for z in (h0, -x * s)]
            out += ["[[shape]]", f'name = "prism{k}"', 'type = "vertices"', vertices(pts), "",
                    "[[particle]]", f'label = "b{i}{j}"', f'shape = "prism{k}"', 'material = "rock"', ""]
            k += 1
    out += ["[output]", "series_every = 100", "snapshot_every = 5000", 'monitor = ["b00", "b37"]', "",
            "[[check]]", 'name = "mean speed at the end"', 'kind = "mean_speed"', 'expected = "1e-4 m/s"',
            'compare = "max"', 'reference = "BENCHMARKS.md S-WEDGE-32: mean speed < 1e-4 m/s after settling"', "",
            "[[check]]", 'name = "largest block displacement"', 'kind = "displacement"',
            "particle = \"" + ", ".join(f"b{i}{j}" for i in range(4) for j in range(8)) + "\"",
            'expected = "1 mm"', 'compare = "max"',
            'reference = "Keissar fig. 2.11d: the blocks stay once friction is mobilised"', ""]
    return "\n".join(out)


with open("D-WEDGE-SLIDE.toml", "w") as f:
    f.write(wedge_slide())
with open("S-WEDGE-32.toml", "w") as f:
    f.write(wedge_32())

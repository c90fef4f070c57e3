#!/usr/bin/python3
"""Writes P-BOX-FILL.toml: 735 cubes of 1 mm fall into a 13 mm box and settle (Zhao section 5.5,
figs. 40-41, table 6: 16,112 s of CPU time with the distance potential, 916,166 s with FDEM).

The cubes start on a 7 x 7 x 15 lattice 1.8 mm apart inside the box's walls (1.8 mm > the cube's
diameter of 1.73 mm, so no two overlap in any orientation), each turned at random (seeded: the
same scene every time). The box is 13 x 13 x 13 mm inside, on a wider base plate that catches any
cube thrown over a wall.

Run from benchmark_scenes/ (numpy only):  /usr/bin/python3 tools/make_box_fill.py
"""
import numpy as np

SEED = 20240735
N = (7, 7, 15)
SPACING = 1.8e-3
EDGE = 1e-3
BOX = 13e-3
WALL = 1e-3

HEADER = """# P-BOX-FILL (Zhao section 5.5, figs. 40-41, table 6): 735 cubes of 1 mm fall into a 13 mm box
# and settle (its walls rise 30 mm, above the cubes' start, so that none bounces out). The figure
# is the wall time to settle, beside the paper's 16,112 s (distance potential) and 916,166 s
# (FDEM, each cube five tetrahedra). Written by tools/make_box_fill.py; edit that, not this.
#
# mu = 0.4877 and a damping ratio of 0.01 as the paper (section 5.5); density 2000 (the paper's
# other examples). The paper gives no stiffness here: its 2 GPa elsewhere is, between 1 mm faces,
# a spring of 2 GPa x 1 mm^2 / 0.5 mm = 4 kN/m. The run lasts 0.6 s; the check says when the mean
# speed of the cubes first falls below 1e-3 m/s (one cube length per second) and that it stays
# there.

[scene]
id = "P-BOX-FILL"
title = "735 cubes of 1 mm fall into a 13 mm box and settle"
source = "Zhao section 5.5, figs. 40-41, table 6; BENCHMARKS.md P-BOX-FILL"

[simulation]
kernel = "gjk-epa-ipm"
dt = "4e-6 s"
end_time = "0.6 s"

[domain]
min = [-0.016, -0.016, -0.004]
max = [0.029, 0.029, 0.032]

[[material]]
name = "cube"
density = "2000 kg/m^3"
kn = "4 kN/m"
ks = "3.2 kN/m"
penalty = "2 GPa"   # distance-potential: Zhao's own value
friction_angle = 25.998   # mu = 0.4877
normal_damping = 0.01

[[shape]]
name = "cube"
type = "cube"
edge = "1 mm"

[[shape]]
name = "base"
type = "box"
min = ["-15 mm", "-15 mm", "-1 mm"]
max = ["28 mm", "28 mm", "0 mm"]

[[shape]]
name = "wall_x"
type = "box"
size = ["1 mm", "15 mm", "30 mm"]

[[shape]]
name = "wall_y"
type = "box"
size = ["13 mm", "1 mm", "30 mm"]

[[particle]]
label = "base"
shape = "base"
material = "cube"
fixed = true

[[particle]]
label = "wall_west"
shape = "wall_x"
material = "cube"
fixed = true
position = ["-0.5 mm", "6.5 mm", "15 mm"]

[[particle]]
label = "wall_east"
shape = "wall_x"
material = "cube"
fixed = true
position = ["13.5 mm", "6.5 mm", "15 mm"]

[[particle]]
label = "wall_south"
shape = "wall_y"
material = "cube"
fixed = true
position = ["6.5 mm", "-0.5 mm", "15 mm"]

[[particle]]
label = "wall_north"
shape = "wall_y"
material = "cube"
fixed = true
position = ["6.5 mm", "13.5 mm", "15 mm"]
"""

FOOTER = """
[output]
series_every = 200
snapshot_every = 4000

[[check]]
name = "settled: time the mean speed falls below 1e-3 m/s"
kind = "free_motion"
quantity = "mean_speed"
at = "first_below"
limit = "1e-3 m/s"
after = "0.05 s"
every = 200
compare = "report"
reference = "Zhao fig. 41: the cubes come to rest in the box"

[[check]]
name = "at rest at the end"
kind = "free_motion"
quantity = "mean_speed"
expected = "1e-3 m/s"
compare = "max"
reference = "Zhao fig. 41"
"""


def random_quaternion(rng):
    """Uniform over rotations (Shoemake 1992)."""
    u1, u2, u3 = rng.random(3)
    a, b = np.sqrt(1 - u1), np.sqrt(u1)
    return (b * np.cos(2 * np.pi * u3), a * np.sin(2 * np.pi * u2), a * np.cos(2 * np.pi * u2),
            b * np.sin(2 * np.pi * u3))


def main():
    rng = np.random.default_rng(SEED)
    offset = 0.5 * (BOX - (N[0] - 1) * SPACING)
    text = HEADER
    n = 0
    for k in range(N[2]):
        for j in range(N[1]):
            for i in range(N[0]):
                x = offset + i * SPACING
                y = offset + j * SPACING
                z = 1.0e-3 + k * SPACING
                q = random_quaternion(rng)
                text += (f'\n[[particle]]\nlabel = "c{n}"\nshape = "cube"\nmaterial = "cube"\n'
                         f"position = [{x:.6g}, {y:.6g}, {z:.6g}]\n"
                         f"rotation = {{ quaternion = [{q[0]:.9f}, {q[1]:.9f}, {q[2]:.9f}, "
                         f"{q[3]:.9f}] }}\n")
                n += 1
    assert n == 735
    text += FOOTER
    with open("P-BOX-FILL.toml", "w") as f:
        f.write(text)


if __name__ == "__main__":
    main()

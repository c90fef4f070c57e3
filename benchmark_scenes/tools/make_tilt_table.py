#!/usr/bin/python3
"""Writes A-TILT-TABLE.toml: the five block slopes of Zhao section 5.3 (after Li et al. 2007) on
one platform tilted at 0.03 rad/s.

Zhao's table 2 only draws the slopes (lost in the text copy); its captions say which blocks and
which joints: big blocks 0.2 x 0.1 x 0.1 m, medium 0.1 m cubes, small 0.05 m cubes (table 3);
persistent joints (every vertical joint runs through the whole slope: columns) or stepped joints
(each layer offset by half a block: brick bond). The slopes here keep that and are sized so that a
rigid-block estimate puts their failure where the experiment did:

  1 big, persistent:    staircase of columns 0.2 m wide, 5, 4, 3, 2, 1 blocks high. The back
                        column alone topples at atan(0.2 / 0.5) = 21.8 deg, the next at 26.6:
                        leaning on each other they topple in between (experiment 22.1-24.2).
  2 big, stepped:       pyramid of 5 brick layers (5, 4, 3, 2, 1 bricks, each layer offset by
                        0.1 m): cannot topple, slides on the platform at the friction angle,
                        atan(0.4877) = 26.0 deg (experiment 25.0-26.3).
  3 medium, persistent: staircase of columns 0.1 m wide, 6 .. 1 cubes high: the back column
                        alone topples at atan(1 / 6) = 9.5 deg, the next at 11.3 (experiment
                        9.8-11.6).
  4 medium, stepped:    pyramid of 6 cube layers offset by 0.05 m (experiment: sliding 23.0-24.9).
  5 mixture:            4 layers of big bricks (stepped) on a 0.1 m bed of small cubes with
                        persistent joints (2 x 2 x 20 columns) (experiment: sliding 19.5-21.8).

The persistent slopes are [[rock_mass]] entries (a staircase profile cut by vertical and
horizontal joint sets); the stepped ones are rows of [[particle_grid]]. Slopes stand 0.2 m apart
along y on a platform that turns about the y axis (its +x end going down) from t = 0.5 s, after
the blocks have settled.

Run from benchmark_scenes/:  /usr/bin/python3 tools/make_tilt_table.py
"""

import math

MU = 0.4877
TILT_RATE = 0.03          # rad/s
START = 0.5               # s: the platform starts turning
END_ANGLE = 28.0          # deg: the run ends there (every slope of the table has failed by then)
GAP = 0.3                 # m between the slopes' y positions

HEADER = f"""# A-TILT-TABLE (Zhao section 5.3, tables 2-5, after Li et al. 2007): five slopes of big, medium
# and small blocks on a platform tilted at 0.03 rad/s; each fails by toppling or sliding at an
# angle the experiment measured. Written by tools/make_tilt_table.py (which explains how the
# five slopes, drawn in the paper's table 2, were reconstructed); edit that, not this.
#
# mu = 0.4877 (26.0 deg) everywhere, C = 2.14 Pa (on a 0.1 m face: 0.0214 N per contact, which
# the law takes per contact), ks / kn = 0.8, density 2000. Zhao's penalty of 2 GPa would be a
# spring of 2 GPa x face area x (1 / r_A + 1 / r_B) = 0.8 GN/m between 0.1 m faces (r the
# inradius: docs/kernels/distance-potential.md; 0.4 GN/m between the 0.05 m cubes); the springs
# here are twenty times softer, which leaves the blocks' overlaps and
# elastic slips below 1e-6 m (a quasi-static tilt does not depend on them) and allows a time step
# of 1e-5 s (the 0.05 m cubes' rotation sets it). The distance potential keeps Zhao's 2 GPa.
# The platform turns from t = {START} s; the tilt at time t is 0.03 (t - {START}) rad.

[scene]
id = "A-TILT-TABLE"
title = "Five block slopes on a tilting table: failure mode and angle"
source = "Zhao section 5.3, tables 2-5; Li et al. 2007; BENCHMARKS.md A-TILT-TABLE"

[simulation]
kernel = "gjk-epa-ipm"
dt = "1e-5 s"
end_time = "{START + math.radians(END_ANGLE) / TILT_RATE:.4f} s"

[domain]
min = [-1, -0.5, -1.6]
max = [2.5, 2, 1.5]

[[material]]
name = "block"
density = "2000 kg/m^3"
kn = "0.04 GN/m"
ks = "0.032 GN/m"
penalty = "2 GPa"   # distance-potential: Zhao's own value
friction_angle = {math.degrees(math.atan(MU)):.6f}   # mu = {MU}
cohesion = "0.0214 N"
normal_damping = 0.3
local_damping = 0.1

[[material]]
name = "small"      # the 0.05 m cubes: a spring of half the stiffness, as the rule above gives
density = "2000 kg/m^3"
kn = "0.02 GN/m"
ks = "0.016 GN/m"
penalty = "2 GPa"
friction_angle = {math.degrees(math.atan(MU)):.6f}
cohesion = "0.0054 N"   # 2.14 Pa on a 0.05 m face
normal_damping = 0.3
local_damping = 0.1

[[driver]]
name = "tilt"
angular_velocity = [0, {TILT_RATE}, 0]
pivot = [0, 0, 0]
start_time = "{START} s"

[[shape]]
name = "platform"
type = "box"
min = [-0.3, -0.2, -0.05]
max = [1.5, {4 * GAP + 0.3:.2f}, 0]

[[shape]]
name = "big"
type = "box"
size = [0.2, 0.1, 0.1]

[[shape]]
name = "medium"
type = "cube"
edge = 0.1

[[shape]]
name = "floor"      # catches the blocks that leave the platform
type = "box"
min = [-1, -0.5, -1.5]
max = [2.5, 2, -1.4]

[[particle]]
label = "platform"
shape = "platform"
material = "block"
driver = "tilt"

[[particle]]
label = "floor"
shape = "floor"
material = "block"
fixed = true
"""


def staircase(width, columns, layer):
    """Profile (x, z) of columns `width` wide, the back one `columns` layers high, the front one 1."""
    pts = [(0.0, 0.0), (width * columns, 0.0)]
    for c in range(columns - 1, -1, -1):
        top = (columns - c) * layer
        pts += [(width * (c + 1), top), (width * c, top)]
    out = []
    for p in pts:
        p = (round(p[0], 6), round(p[1], 6))
        if not out or out[-1] != p:
            out.append(p)
    return out


def rock_mass(name, width, columns, layer, y0, depth):
    profile = ", ".join(f"[{x:g}, {z:g}]" for x, z in staircase(width, columns, layer))
    return f"""
[[rock_mass]]
name = "{name}"
material = "block"
region = {{ type = "profile", profile = [{profile}], y = [{y0:g}, {y0 + depth:g}] }}

[[rock_mass.joint_set]]
name = "columns"
dip = 90
dip_direction = 90
spacing = "{width:g} m"

[[rock_mass.joint_set]]
name = "layers"
dip = 0
dip_direction = 0
spacing = "{layer:g} m"
"""


def brick_layers(name, shape, length, height, layers, y):
    """A pyramid of `layers` layers: layer k holds layers - k blocks, offset by half a block."""
    out = ""
    for k in range(layers):
        out += f"""
[[particle_grid]]
shape = "{shape}"
material = "block"
label_prefix = "{name}_{k}"
origin = [{0.5 * length * (k + 1):g}, {y:g}, {height * (k + 0.5):g}]
spacing = [{length:g}, 1, 1]
count = [{layers - k}, 1, 1]
"""
    return out


def checks(name, mode, low, high, source):
    mid, half = 0.5 * (low + high), 0.5 * (high - low)
    mode_check = ('compare = "min"\nexpected = "2 deg"' if mode == "toppling"
                  else 'compare = "max"\nexpected = "2 deg"')
    return f"""
[[check]]
name = "{name}: failure angle"
kind = "tilt_failure"
platform = "platform"
label_prefix = "{name}"
threshold = "2 mm"
expected = "{mid:g} deg"
tolerance = "{half:g} deg"
reference = "Li et al. 2007 experiment {low}-{high} deg (Zhao table 5); Zhao: {source}"

[[check]]
name = "{name}: {mode} (slope's turn when a block has moved 5 cm)"
kind = "tilt_failure"
platform = "platform"
label_prefix = "{name}"
measure = "rotation"
reach = "0.05 m"
{mode_check}
reference = "Zhao table 4: {mode}"
"""


def slope5():
    """Slope 5: a bed of 0.05 m cubes (persistent joints) under 4 stepped layers of big bricks."""
    text = f"""
[[rock_mass]]
name = "s5"
material = "small"
region = {{ type = "box", min = [0, {4 * GAP:g}, 0], max = [1, {4 * GAP + 0.1:g}, 0.1] }}

[[rock_mass.joint_set]]
name = "x"
dip = 90
dip_direction = 90
spacing = "0.05 m"

[[rock_mass.joint_set]]
name = "y"
dip = 90
dip_direction = 0
spacing = "0.05 m"

[[rock_mass.joint_set]]
name = "layers"
dip = 0
dip_direction = 0
spacing = "0.05 m"
"""
    for k in range(4):
        text += f"""
[[particle_grid]]
shape = "big"
material = "block"
label_prefix = "s5_top{k}"
origin = [{0.1 * (k + 1):g}, {4 * GAP + 0.05:g}, {0.1 + 0.1 * (k + 0.5):g}]
spacing = [0.2, 1, 1]
count = [{5 - k}, 1, 1]
"""
    return text


def main():
    text = HEADER
    text += rock_mass("s1", 0.2, 5, 0.1, 0.0, 0.1)
    text += brick_layers("s2", "big", 0.2, 0.1, 5, GAP + 0.05)
    text += rock_mass("s3", 0.1, 6, 0.1, 2 * GAP, 0.1)
    text += brick_layers("s4", "medium", 0.1, 0.1, 6, 3 * GAP + 0.05)
    text += slope5()
    text += """
[output]
series_every = 2000
snapshot_every = 20000
"""
    text += checks("s1", "toppling", 22.1, 24.2, "toppling 24 deg; Li: 23.0")
    text += checks("s2", "sliding", 25.0, 26.3, "sliding 26 deg; Li: 25.5")
    text += checks("s3", "toppling", 9.8, 11.6, "toppling 11 deg; Li: 10.0")
    text += checks("s4", "sliding", 23.0, 24.9, "sliding 24 deg; Li: 23.5")
    text += checks("s5", "sliding", 19.5, 21.8, "sliding 21 deg; Li: 20.0")
    with open("A-TILT-TABLE.toml", "w") as f:
        f.write(text)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Writes D-HEX-ROD.toml (Keissar figs. 3.7-3.8, table 3.8) and D-TETRA-IMPACT.toml (Zhao 5.1)."""
import math


def vec(v):
    return "[" + ", ".join(f"{x:.12g}" for x in v) + "]"


def hex_rod():
    slope = 30.0
    t = math.radians(slope)
    n = (math.sin(t), 0.0, math.cos(t))     # slope normal (dip towards +x)
    d = (math.cos(t), 0.0, -math.sin(t))    # down the dip
    R, length, offset = 0.3, 2.0, 0.6
    # Hexagon corners in the slope frame (along d, along n): one corner points into the slope.
    corners = [(R * math.cos(math.radians(-90 + 60 * k)), R * math.sin(math.radians(-90 + 60 * k)))
               for k in range(6)]
    pts = []
    for y in (-length / 2, length / 2):
        for (u, w) in corners:
            pts.append(tuple(u * d[i] + w * n[i] + (y if i == 1 else 0.0) for i in range(3)))
    centre = tuple(R * n[i] for i in range(3))  # resting on the lowest edge
    slope_pos = tuple(6.0 * d[i] - 1.0 * n[i] for i in range(3))
    return "\n".join([
        "# D-HEX-ROD (Keissar section 3.3, figs. 3.7-3.8, table 3.8): a hexagonal rod, axis horizontal,",
        "# stands on one of its edges on a 30 deg slope, shifted along its axis off the slope block's",
        "# centre. It should tip over and roll straight down the dip. The contact alternates between",
        "# edge-face and face-face; an off-centre contact point along the rod's axis torques it about",
        "# the slope normal and it drifts sideways. Thesis: only FCP with IPM rolls straight.",
        "#", "# Written by tools/make_rod_tetra_scenes.py; edit that, not this.", "",
        "[scene]", 'id = "D-HEX-ROD"', 'title = "Hexagonal rod rolling down a 30 degree slope"',
        'source = "Keissar figs. 3.7-3.8, table 3.8; BENCHMARKS.md D-HEX-ROD"', "",
        "[simulation]", 'kernel = "fcp-ipm"', 'dt = "5e-5 s"', 'end_time = "2 s"', "",
        "[domain]", "min = [-4, -3, -12]", "max = [18, 4, 4]", "",
        "[[material]]", 'name = "rock"', 'density = "2650 kg/m^3"', 'kn = "1 GN/m"',
        'penalty = "0.5 GPa"   # distance-potential: about kn x inradius / contact area', 'ks = "0.5 GN/m"',
        "friction_angle = 40", "normal_damping = 0.1", "",
        "[[shape]]", 'name = "slope"', 'type = "box"', "size = [20, 4, 2]",
        f"rotation = {{ axis = [0, 1, 0], angle = {slope} }}", "",
        "[[shape]]", 'name = "rod"', 'type = "vertices"',
        "vertices = [" + ", ".join(vec(p) for p in pts) + "]", "",
        "[[particle]]", 'label = "slope"', 'shape = "slope"', 'material = "rock"', "fixed = true",
        f"position = {vec(slope_pos)}", "",
        "[[particle]]", 'label = "rod"', 'shape = "rod"', 'material = "rock"',
        f"position = {vec((centre[0], offset, centre[2]))}   # {offset} m off the slope's centre line", "",
        "[output]", "series_every = 100", "snapshot_every = 2000", 'monitor = ["rod"]', "",
        "[[check]]", 'name = "lateral drift"', 'kind = "lateral_drift"', 'particle = "rod"',
        f"direction = {vec(d)}", "lateral = [0, 1, 0]", "expected = 1e-3", 'compare = "max"',
        'reference = "BENCHMARKS.md D-HEX-ROD: lateral drift < 1e-3 of the travel"', "",
        "[[check]]", 'name = "travel down the dip"', 'kind = "displacement"', 'particle = "rod"',
        f"direction = {vec(d)}", 'at = "end"', 'compare = "report"',
        'reference = "how far the rod rolled"', ""])


def tetra_impact():
    h = 0.5 / math.sqrt(2.0)  # regular tetrahedron of edge 1: corners (+-1/2, 0, -h), (0, +-1/2, h)
    block = [(0.5, 0, -h), (-0.5, 0, -h), (0, 0.5, h), (0, -0.5, h)]
    # The fixed base: its top ridge runs along y at z = 0 and both faces at the ridge slope at 45
    # deg (mirror images under x -> -x), but its other two corners lie at different distances from
    # the ridge, so the base as a whole is irregular.
    base = [(0, -0.6, 0), (0, 0.6, 0), (-0.5, 0.0, -0.5), (0.9, 0.2, -0.9)]
    drop = 0.5
    return "\n".join([
        "# D-TETRA-IMPACT (Zhao section 5.1, figs. 23-27): a regular tetrahedron (edge 1 m) falls from",
        "# rest and hits, with its lowest edge, the top ridge of a fixed tetrahedron, crossing it at",
        "# right angles (g = 10, density 2000, no friction, no damping). Both faces at the ridge slope",
        "# at 45 deg, so near the contact the set-up is mirror-symmetric (x -> -x, y -> -y): the force",
        "# must stay vertical, the block must not drift sideways nor turn, and it must rebound with the",
        "# kinetic energy it had before the contact (Zhao fig. 27). The fixed tetrahedron is irregular",
        "# away from the ridge: its two ridge faces have different heights H over them. The FDEM",
        "# potential scales each face by H/4 (Zhao eq. 1, section 2.2), the distance potential by the",
        "# inscribed radius r of the whole body (eq. 5): FDEM pushes the block sideways (Zhao fig. 24),",
        "# the distance potential does not (fig. 25). A small penalty lets the overlap grow large",
        "# enough to see (Zhao: 'large embedding is allowed').",
        "#", "# Written by tools/make_rod_tetra_scenes.py; edit that, not this.", "",
        "[scene]", 'id = "D-TETRA-IMPACT"', 'title = "Tetrahedron dropped onto a tetrahedron\'s ridge"',
        'source = "Zhao section 5.1, figs. 23-27; BENCHMARKS.md D-TETRA-IMPACT"', "",
        "[simulation]", 'kernel = "distance-potential"', 'dt = "1e-4 s"', 'end_time = "0.8 s"',
        "gravity = [0, 0, -10]", "",
        "[domain]", "min = [-2, -2, -2]", "max = [2, 2, 3]", "",
        "[[material]]", 'name = "rock"', 'density = "2000 kg/m^3"', 'penalty = "0.1 GPa"',
        'kn = "20 MN/m"   # for the penalty kernels (gjk-epa, fcp, ...) run on this scene',
        "ks = 0", "friction_angle = 0", "",
        "[[shape]]", 'name = "block"', 'type = "vertices"',
        "vertices = [" + ", ".join(vec(p) for p in block) + "]", "",
        "[[shape]]", 'name = "base"', 'type = "vertices"',
        "vertices = [" + ", ".join(vec(p) for p in base) + "]", "",
        "[[particle]]", 'label = "base"', 'shape = "base"', 'material = "rock"', "fixed = true", "",
        "[[particle]]", 'label = "block"', 'shape = "block"', 'material = "rock"',
        "# its lowest edge runs along x, across the base's ridge along y",
        f"position = [0, 0, {h + drop:.12g}]   # lowest edge {drop} m above the ridge", "",
        "[output]", "series_every = 10", 'monitor = ["block"]', "",
        "[[check]]", 'name = "energy after rebound"', 'kind = "kinetic_energy_ratio"', 'particle = "block"',
        "expected = 1", "tolerance = 0.01", 'compare = "abs"',
        'reference = "Zhao fig. 27; BENCHMARKS.md: < 1 % loss"', "",
        "[[check]]", 'name = "sideways drift x"', 'kind = "displacement"', 'particle = "block"',
        "direction = [1, 0, 0]", 'expected = "1e-6 m"', 'compare = "max"',
        'reference = "Zhao figs. 24-25: no sideways deflection"', "",
        "[[check]]", 'name = "sideways drift y"', 'kind = "displacement"', 'particle = "block"',
        "direction = [0, 1, 0]", 'expected = "1e-6 m"', 'compare = "max"',
        'reference = "Zhao figs. 24-25: no sideways deflection"', "",
        "[[check]]", 'name = "rotation"', 'kind = "rotation"', 'particle = "block"', "expected = 1e-6",
        'compare = "max"', 'reference = "symmetry of the set-up near the contact"', ""])


with open("D-HEX-ROD.toml", "w") as f:
    f.write(hex_rod())
with open("D-TETRA-IMPACT.toml", "w") as f:
    f.write(tetra_impact())

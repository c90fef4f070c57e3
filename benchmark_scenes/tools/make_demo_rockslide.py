#!/usr/bin/python3
"""Writes demo-rockslide.toml: a jointed rock slab sliding down a steep slope onto a runout floor.

The slab is a convex polyhedron (a box lying on the slope); three joint sets cut it into convex
blocks. Each cut of a convex polyhedron by a plane gives two convex polyhedra, so the blocks are
computed here exactly: a block is the intersection of half-spaces n . x <= d, its corners are the
points where three of its planes meet and that satisfy all the others. Joint positions and
orientations are jittered from a fixed seed, so the blocks are irregular but the file is the same
on every run. A joint that would cut a sliver (thinner than MIN_THICKNESS_FRACTION of its
spacing) off a block stops there instead, as real joints do, and bars left by such joints are
split across their long axis: no block is tiny or slender, so the critical time step (set by
the worst block's rotation) stays near that of a nominal block.

Sized for the README's main job: 2 ranks, about a minute on 2 cores. Large blocks (nominal
4 x 5.5 x 5.5 m) with kn = 1 GN/m allow dt = 5e-4 s (polydem suggests 6.0e-4 s); the number of
steps to a given runout falls as the scene grows (time ~ sqrt(L / g), dt ~ sqrt(m / k) ~ L^1.5).

Run from benchmark_scenes/ with numpy only:  /usr/bin/python3 tools/make_demo_rockslide.py
"""
import math

import numpy as np

SEED = 20240611
SLOPE_DEG = 40.0          # dip of the sliding surface
SLOPE_LENGTH = 52.0       # m, along the dip, from the crest to the toe
SLOPE_WIDTH = 60.0        # m, along the strike (y) of the fixed slope body
SLAB_LENGTH = 36.0        # m, along the dip
SLAB_WIDTH = 24.0         # m, along the strike
SLAB_THICKNESS = 8.0      # m, normal to the slope
SLAB_OFFSET = 2.0         # m, from the crest down to the slab's upper end
RUNOUT_LENGTH = 80.0      # m, of the floor beyond the toe
BODY_DEPTH = 6.0          # m, thickness of the fixed bodies

# Joint sets, in the slope frame (u down the dip, y along the strike, w out of the slope):
# (name, unit normal, mean spacing in m, orientation jitter in deg)
JOINT_SETS = [
    ("bedding", (0.0, 0.0, 1.0), 4.0, 3.0),                     # parallel to the sliding surface
    ("cross", (math.cos(math.radians(-20)), 0.0, math.sin(math.radians(-20))), 5.5, 8.0),
    ("oblique", (math.sin(math.radians(30)), math.cos(math.radians(30)), 0.0), 5.5, 8.0),
]
POSITION_JITTER = 0.25    # fraction of the spacing
MIN_THICKNESS_FRACTION = 0.6  # of the spacing: no piece thinner than this along a cut normal
MAX_ASPECT = 2.0          # blocks longer than this times the largest spacing are split across

ROCK = {"density": 2650, "kn": "1 GN/m", "ks": "0.5 GN/m", "friction_angle": 30,
        "normal_damping": 0.2, "local_damping": 0.02}
SLIDING_SURFACE_FRICTION = 24  # deg: a weathered, clay-filled bedding plane, below the dip
FLOOR_FRICTION = 35            # deg: rough valley floor

DT = "5e-4 s"
END_TIME = "9 s"
SNAPSHOT_EVERY = 200        # steps: 0.1 s of motion per frame
SERIES_EVERY = 40


def vec(v):
    return "[" + ", ".join(f"{x:.9g}" if abs(x) > 1e-12 else "0" for x in v) + "]"


# --- convex polyhedra as half-space lists -------------------------------------------------------

def corners(planes):
    """Corners of {x : n . x <= d for all (n, d)}: triple intersections that satisfy every plane."""
    n = np.array([p[0] for p in planes])
    d = np.array([p[1] for p in planes])
    scale = max(1.0, float(np.max(np.abs(d))))
    pts = []
    m = len(planes)
    for i in range(m):
        for j in range(i + 1, m):
            for k in range(j + 1, m):
                a = n[[i, j, k]]
                if abs(np.linalg.det(a)) < 1e-9:
                    continue
                x = np.linalg.solve(a, d[[i, j, k]])
                if np.all(n @ x <= d + 1e-9 * scale):
                    if not any(np.linalg.norm(x - q) < 1e-7 * scale for q in pts):
                        pts.append(x)
    return np.array(pts)


def volume(planes, pts):
    """Volume of the polyhedron: pyramids from the centroid of its corners to each face polygon."""
    if len(pts) < 4:
        return 0.0
    c = pts.mean(axis=0)
    scale = max(1.0, float(np.max(np.abs(pts))))
    vol = 0.0
    for nrm, dd in planes:
        on = pts[np.abs(pts @ nrm - dd) < 1e-8 * scale]
        if len(on) < 3:
            continue
        fc = on.mean(axis=0)
        e1 = on[0] - fc
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(nrm, e1)
        ang = np.arctan2((on - fc) @ e2, (on - fc) @ e1)
        poly = on[np.argsort(ang)]
        area = 0.0
        for a, b in zip(poly, np.roll(poly, -1, axis=0)):
            area += 0.5 * np.dot(np.cross(a - fc, b - fc), nrm)
        vol += area * (dd - np.dot(nrm, c)) / 3.0
    return vol


def cut(block, nrm, dd, min_thickness):
    """Splits a block (planes, corners, volume) by n . x = d; None if a piece would be a sliver
    (thinner than min_thickness along n)."""
    planes, pts, vol = block
    side = pts @ nrm - dd
    if side.max() < min_thickness or -side.min() < min_thickness:
        return None
    lo = planes + [(nrm, dd)]
    hi = planes + [(-nrm, -dd)]
    plo, phi = corners(lo), corners(hi)
    return (lo, plo, volume(lo, plo)), (hi, phi, volume(hi, phi))


def longest_axis(pts):
    """Unit direction of the largest extent of the points (principal axis of their spread)."""
    d = pts - pts.mean(axis=0)
    w, v = np.linalg.eigh(d.T @ d)
    axis = v[:, -1]
    ext = d @ axis
    return axis, float(ext.max() - ext.min())


def unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def jittered_normal(rng, base, jitter_deg):
    base = unit(base)
    # Two directions across the normal; tilt by a random angle about a random axis in that plane.
    helper = np.array([0.0, 0.0, 1.0]) if abs(base[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    a = unit(np.cross(base, helper))
    b = np.cross(base, a)
    phi = rng.uniform(0, 2 * math.pi)
    tilt = math.radians(rng.uniform(-jitter_deg, jitter_deg))
    axis = math.cos(phi) * a + math.sin(phi) * b
    return unit(math.cos(tilt) * base + math.sin(tilt) * axis)


def blocks_of_slab():
    """The slab in the slope frame (u, y, w), cut by the joint sets; returns the blocks' corners."""
    rng = np.random.default_rng(SEED)
    half_w = 0.5 * SLAB_WIDTH
    box = [(np.array([1.0, 0, 0]), SLAB_LENGTH), (np.array([-1.0, 0, 0]), 0.0),
           (np.array([0, 1.0, 0]), half_w), (np.array([0, -1.0, 0]), half_w),
           (np.array([0, 0, 1.0]), SLAB_THICKNESS), (np.array([0, 0, -1.0]), 0.0)]
    pts = corners(box)
    blocks = [(box, pts, volume(box, pts))]
    nominal = np.prod([s for (_, _, s, _) in JOINT_SETS])
    centre = np.array([0.5 * SLAB_LENGTH, 0.0, 0.5 * SLAB_THICKNESS])
    for name, normal, spacing, jitter in JOINT_SETS:
        # The planes of a set cover the slab: offsets along the mean normal from the slab's extent.
        base = unit(normal)
        allpts = np.vstack([b[1] for b in blocks])
        proj = allpts @ base
        lo, hi = proj.min(), proj.max()
        count = int(math.floor((hi - lo) / spacing))
        first = lo + 0.5 * ((hi - lo) - (count - 1) * spacing) if count > 0 else 0
        for i in range(count):
            nrm = jittered_normal(rng, base, jitter)
            offset = first + i * spacing + rng.uniform(-POSITION_JITTER, POSITION_JITTER) * spacing
            # The plane through the point `offset` along the mean normal from the slab's centre line.
            point = centre + (offset - centre @ base) * base
            dd = float(nrm @ point)
            split = []
            for blk in blocks:
                r = cut(blk, nrm, dd, MIN_THICKNESS_FRACTION * spacing)
                split.extend(r if r else [blk])
            blocks = split
    # Joints that stopped short can leave long bars (R large, I small: they set the time step);
    # split each across its longest axis, through its centre, until none is too long.
    longest = MAX_ASPECT * max(s for (_, _, s, _) in JOINT_SETS)
    done = False
    while not done:
        done = True
        split = []
        for blk in blocks:
            axis, length = longest_axis(blk[1])
            r = cut(blk, axis, float(axis @ blk[1].mean(axis=0)), 0.25 * length) if length > longest else None
            split.extend(r if r else [blk])
            done = done and r is None
        blocks = split
    return [b[1] for b in blocks], [b[2] for b in blocks], nominal


def main():
    theta = math.radians(SLOPE_DEG)
    s, c = math.sin(theta), math.cos(theta)
    # Slope frame -> world: u (down the dip) = (c, 0, -s), w (out of the slope) = (s, 0, c).
    # The crest of the sliding surface is at the origin; the toe at x_toe, z_toe.
    frame = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])  # columns u, y, w
    x_toe, z_toe = SLOPE_LENGTH * c, -SLOPE_LENGTH * s

    corners_uyw, volumes, nominal = blocks_of_slab()
    shift = np.array([SLAB_OFFSET, 0.0, 0.0])
    world = [(frame @ (p + shift).T).T for p in corners_uyw]
    total = sum(volumes)
    order = sorted(range(len(world)), key=lambda i: (round(float(world[i].mean(0)[2]), 6),
                                                      round(float(world[i].mean(0)[0]), 6),
                                                      round(float(world[i].mean(0)[1]), 6)))

    # Fixed bodies, as prisms along y (section in x, z): the slope body under the sliding
    # surface, ending in a face normal to the slope at the toe (that face lies under the floor),
    # and the floor, a flat slab whose top is at the toe's height.
    half = 0.5 * SLOPE_WIDTH
    up = -BODY_DEPTH * s - 1.0  # a short flat bench behind the crest
    slope_sec = [(up, 0.0), (0.0, 0.0), (x_toe, z_toe), (x_toe - BODY_DEPTH * s, z_toe - BODY_DEPTH * c),
                 (up, -BODY_DEPTH * c)]
    floor_x0 = x_toe - 2.0
    floor_x1 = x_toe + RUNOUT_LENGTH
    floor_sec = [(floor_x0, z_toe), (floor_x1, z_toe), (floor_x1, z_toe - BODY_DEPTH),
                 (floor_x0, z_toe - BODY_DEPTH)]
    floor_half = 0.5 * SLOPE_WIDTH + 10.0

    def prism(sec, hw):
        return [(x, y, z) for (x, z) in sec for y in (-hw, hw)]

    top = max(float(w[:, 2].max()) for w in world)
    dmin = [-3.0, -floor_half, z_toe - 1.0]
    dmax = [floor_x1, floor_half, top + 2.0]

    out = [
        f"# demo-rockslide: the README's main job. A jointed rock slab on a {SLOPE_DEG:g} deg slope fails along",
        f"# its clay-filled base ({SLIDING_SURFACE_FRICTION} deg < {SLOPE_DEG:g} deg), breaks up along its joints "
        f"(friction {ROCK['friction_angle']} deg) and runs",
        "# out onto a rough valley floor. The slab (" + f"{SLAB_LENGTH:g} x {SLAB_WIDTH:g} x "
        f"{SLAB_THICKNESS:g} m along dip x strike x normal) is cut by",
        "# three jittered joint sets (bedding parallel to the slope, cross joints, oblique joints) into",
        f"# {len(world)} convex blocks ({total:.1f} m^3, mean {total / len(world):.2f} m^3, "
        f"smallest {min(volumes):.2f} m^3). The slope and the floor",
        "# are fixed prisms. Axes: x down the dip (horizontal), y along the strike, z up; the crest of",
        f"# the sliding surface is at the origin, its toe at x = {x_toe:.3f} m, z = {z_toe:.3f} m.",
        "#",
        f"# Written by tools/make_demo_rockslide.py (seed {SEED}); edit that, not this.",
        "",
        "[scene]",
        'id = "demo-rockslide"',
        f'title = "Jointed rock slab sliding down a {SLOPE_DEG:g} degree slope onto a runout floor"',
        'source = "benchmark_scenes/tools/make_demo_rockslide.py; docs/demo-rockslide.md"',
        "",
        "[simulation]",
        'kernel = "gjk-epa-ipm"',
        f'dt = "{DT}"',
        f'end_time = "{END_TIME}"',
        "",
        "[domain]",
        f"min = {vec(dmin)}",
        f"max = {vec(dmax)}",
        "blocks = [8, 4, 1]",
        "rebalance_every = 1000",
        "",
        "[[material]]",
        'name = "rock"',
        f'density = "{ROCK["density"]} kg/m^3"',
        f'kn = "{ROCK["kn"]}"',
        f'ks = "{ROCK["ks"]}"',
        f"friction_angle = {ROCK['friction_angle']}",
        f"normal_damping = {ROCK['normal_damping']}",
        f"local_damping = {ROCK['local_damping']}",
        "",
        "[[material]]",
        'name = "slope"',
        f'density = "{ROCK["density"]} kg/m^3"',
        f'kn = "{ROCK["kn"]}"',
        f'ks = "{ROCK["ks"]}"',
        f"friction_angle = {SLIDING_SURFACE_FRICTION}",
        f"normal_damping = {ROCK['normal_damping']}",
        "",
        "[[material]]",
        'name = "floor"',
        f'density = "{ROCK["density"]} kg/m^3"',
        f'kn = "{ROCK["kn"]}"',
        f'ks = "{ROCK["ks"]}"',
        f"friction_angle = {FLOOR_FRICTION}",
        f"normal_damping = {ROCK['normal_damping']}",
        "",
        "[[interaction]]",
        'materials = ["rock", "floor"]',
        f"friction_angle = {FLOOR_FRICTION}",
        "",
        "[[shape]]",
        'name = "slope"',
        'type = "vertices"',
        "vertices = [" + ", ".join(vec(p) for p in prism(slope_sec, half)) + "]",
        "",
        "[[particle]]",
        'label = "slope"',
        'shape = "slope"',
        'material = "slope"',
        "fixed = true",
        "",
        "[[shape]]",
        'name = "floor"',
        'type = "vertices"',
        "vertices = [" + ", ".join(vec(p) for p in prism(floor_sec, floor_half)) + "]",
        "",
        "[[particle]]",
        'label = "floor"',
        'shape = "floor"',
        'material = "floor"',
        "fixed = true",
        "",
    ]
    labels = []
    for k, i in enumerate(order):
        label = f"b{k}"
        labels.append(label)
        out += ["[[shape]]", f'name = "{label}"', 'type = "vertices"',
                "vertices = [" + ", ".join(vec(p) for p in world[i]) + "]", "",
                "[[particle]]", f'label = "{label}"', f'shape = "{label}"', 'material = "rock"', ""]
    # Monitors: the lowest block at the slab's toe end and the highest at its crest end.
    cent = [world[i].mean(0) for i in order]
    toe_block = labels[max(range(len(cent)), key=lambda k: cent[k][0] - 1e-3 * cent[k][2])]
    crest_block = labels[min(range(len(cent)), key=lambda k: cent[k][0] - 1e-3 * cent[k][2])]
    out += [
        "[output]",
        f"series_every = {SERIES_EVERY}",
        f"snapshot_every = {SNAPSHOT_EVERY}",
        f'monitor = ["{toe_block}", "{crest_block}"]',
        "",
        "[[check]]",
        'name = "horizontal travel of the crest block"',
        'kind = "displacement"',
        f'particle = "{crest_block}"',
        "direction = [1, 0, 0]",
        'at = "end"',
        'expected = "10 m"',
        'compare = "min"',
        'reference = "the slab fails (base friction below the dip) and runs out past the toe"',
        "",
        "[[check]]",
        'name = "mean speed at the end"',
        'kind = "mean_speed"',
        'expected = "0.5 m/s"',
        'compare = "max"',
        'reference = "the debris comes to rest on the floor"',
        "",
    ]
    with open("demo-rockslide.toml", "w") as f:
        f.write("\n".join(out))
    print(f"{len(world)} blocks, {total:.1f} m^3, volumes {min(volumes):.2f}..{max(volumes):.2f} m^3 "
          f"(nominal {nominal:.2f}); toe at x = {x_toe:.2f} m, z = {z_toe:.2f} m")


main()

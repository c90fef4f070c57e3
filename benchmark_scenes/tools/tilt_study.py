#!/usr/bin/python3
"""A-TILT-TABLE's slopes run one at a time, on the flat platform as in the benchmark or (the
staircases of columns, slopes 1 and 3) on a stepped base, with a chosen contact kernel and tilt
rate; reports each run's failure onset, 2 mm and 5 cm angles and mode (docs/validation.md,
"A-TILT-TABLE: each slope alone").

Every variant keeps A-TILT-TABLE's materials, platform, floor, settling time and end angle
(28 deg; make_tilt_table.HEADER), the slope's place on the platform and its own checks. Only
that slope stands on the platform, and its blocks are monitored, so that series.csv holds their
history.

  flat:     the slope exactly as in A-TILT-TABLE (tools/make_tilt_table.py).
  stepped:  a staircase's columns (slope 1: 0.2 m wide, 1 .. 5 big blocks high; slope 3: 0.1 m,
            1 .. 6 cubes), each standing on its own tread, Goodman and Bray's geometry: the tread
            under the k-th column from the toe is k b above the platform, b = 0.05 m (half a
            layer; Zhao gives no step: an assumption), a box turning with the platform. A
            column's face is then pressed by its lower neighbour only above that neighbour's
            tread. The domain and the floor that catches the fallen blocks reach 8 m down the
            tilt instead of 2.5 m.
  columns5: slope 3's cubes as six columns of 5 on treads rising b = 0.1 m (one cube): Goodman
            and Bray's regular set, a staircase too, whose limit is that of one column, atan(1/5).

Angles (from series.csv, every 1000 steps): d(t) is the largest displacement of a block of the
slope against the platform since the tilt started (t = 0.5 s, blocks settled), v(t) the largest
speed of a block against the platform. Failure: d reaches REACH = 5 cm (half a 0.1 m block).
Onset (scale-free): the tilt from which v stays above EPS sqrt(g L) (L the slope's smallest
block: 1 mm/s for 0.1 m) until that failure: the first sustained motion (a slip that jams again,
v falling back, is not one). 2 mm: the benchmark's `tilt_failure` check (the first block to move
2 mm, jam or not). The mode is read when a block has first moved 5 cm: the slope's turn, the
`tilt_failure` check's reading (module/run/slope_turn.h: the mass-weighted median turn against
the platform of the blocks that have moved a tenth of 5 cm), toppling when above 2 deg; beside
it the turn of the first block to move 5 cm alone. The two differ when that block is a top cube
sliding off a leaning column. Rigid limit: Goodman and Bray's recursion for the columns
(tests/apps/goodman_bray.py), atan(mu) for the slopes that cannot topple.

Run from the repository root, one case after another (each at full length, 1 rank, nice -n 10):
  /usr/bin/python3 benchmark_scenes/tools/tilt_study.py --cases s1-flat-gjk-0.03 --out results/tilt-study
  /usr/bin/python3 benchmark_scenes/tools/tilt_study.py --table results/tilt-study   (table only)
  /usr/bin/python3 benchmark_scenes/tools/tilt_study.py --goodman-bray   (limit against step rise)
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_tilt_table as mtt  # noqa: E402

EDGE = 0.1            # m: slope 3's cubes
COLUMNS = 6           # slope 3: back column 6 cubes high, toe column 1
X0 = 0.0              # every slope's back end on the platform (as in A-TILT-TABLE)
BIG = 0.2 * 0.1 * 0.1     # m^3: a big block (Zhao table 3)
MEDIUM = 0.1 ** 3
SMALL = 0.05 ** 3
# Each slope as in A-TILT-TABLE (tools/make_tilt_table.py): its y position on the platform, its
# column width and layer height where it is a staircase of columns (None: it is not one), the
# size L of its smallest block (onset), and the experiment's mode and range (Zhao table 5).
SLOPES = {
    "s1": dict(y0=0.0, width=0.2, layer=0.1, L=0.1,
               reference=("toppling", 22.1, 24.2, "toppling 24 deg; Li: 23.0")),
    "s2": dict(y0=mtt.GAP + 0.05, width=None, L=0.1,
               reference=("sliding", 25.0, 26.3, "sliding 26 deg; Li: 25.5")),
    "s3": dict(y0=2 * mtt.GAP, width=0.1, layer=0.1, L=0.1,
               reference=("toppling", 9.8, 11.6, "toppling 11 deg; Li: 10.0")),
    "s4": dict(y0=3 * mtt.GAP + 0.05, width=None, L=0.1,
               reference=("sliding", 23.0, 24.9, "sliding 24 deg; Li: 23.5")),
    "s5": dict(y0=4 * mtt.GAP, width=None, L=0.05,
               reference=("sliding", 19.5, 21.8, "sliding 21 deg; Li: 20.0")),
}
# Each base: the rise b of each tread over the next lower one (m) and the columns' heights in
# layers from the toe up (None: the slope as in A-TILT-TABLE, on the flat platform).
BASES = {
    "flat": (0.0, None),
    "stepped": (0.05, "staircase"),
    "columns5": (0.1, [5] * COLUMNS),
}
REACH = 0.05          # m: failure, and where the mode is read (as the check)
MOVED = 0.1           # the mode counts the blocks that have moved this fraction of REACH
EPS = 1e-3            # onset: sustained speed against the platform, as a fraction of sqrt(g L)
END_ANGLE = 28.0      # deg, as A-TILT-TABLE
GJK, DP = "gjk-epa-ipm", "distance-potential"
CASES = {             # name: (slope, base, kernel, tilt rate rad/s); slope 3's keep short names
    "flat-gjk-0.03": ("s3", "flat", GJK, 0.03),
    "flat-gjk-0.06": ("s3", "flat", GJK, 0.06),
    "stepped-gjk-0.03": ("s3", "stepped", GJK, 0.03),
    "stepped-gjk-0.06": ("s3", "stepped", GJK, 0.06),
    "flat-dp-0.03": ("s3", "flat", DP, 0.03),
    "stepped-dp-0.03": ("s3", "stepped", DP, 0.03),
    "flat-dp-0.06": ("s3", "flat", DP, 0.06),
    "stepped-dp-0.06": ("s3", "stepped", DP, 0.06),
    "columns5-gjk-0.03": ("s3", "columns5", GJK, 0.03),
    "s1-flat-gjk-0.03": ("s1", "flat", GJK, 0.03),
    "s2-flat-gjk-0.03": ("s2", "flat", GJK, 0.03),
    "s4-flat-gjk-0.03": ("s4", "flat", GJK, 0.03),
    "s5-flat-gjk-0.03": ("s5", "flat", GJK, 0.03),
    "s1-stepped-gjk-0.03": ("s1", "stepped", GJK, 0.03),
    "s1-flat-dp-0.03": ("s1", "flat", DP, 0.03),
    "s2-flat-dp-0.03": ("s2", "flat", DP, 0.03),
    "s4-flat-dp-0.03": ("s4", "flat", DP, 0.03),
    "s5-flat-dp-0.03": ("s5", "flat", DP, 0.03),
}


def header(rate, name):
    """A-TILT-TABLE's header at another tilt rate, ending at the same angle."""
    text = mtt.HEADER.replace('id = "A-TILT-TABLE"', f'id = "A-TILT-TABLE-{name}"')
    text = text.replace(f"angular_velocity = [0, {mtt.TILT_RATE}, 0]",
                        f"angular_velocity = [0, {rate:g}, 0]")
    end = mtt.START + math.radians(END_ANGLE) / rate
    old_end = mtt.START + math.radians(mtt.END_ANGLE) / mtt.TILT_RATE
    text = text.replace(f'end_time = "{old_end:.4f} s"', f'end_time = "{end:.4f} s"')
    assert f"[0, {rate:g}, 0]" in text and f"{end:.4f} s" in text
    return (f"# Written by benchmark_scenes/tools/tilt_study.py: A-TILT-TABLE's slope 3 alone, "
            f"{name}.\n" + text)


def flat_slope(slope):
    """The slope exactly as in A-TILT-TABLE; its labels and each block's volume."""
    if slope == "s1":
        return mtt.rock_mass("s1", 0.2, 5, 0.1, SLOPES["s1"]["y0"], 0.1), {f"s1_{i}": BIG
                                                                          for i in range(15)}
    if slope == "s3":
        return mtt.rock_mass("s3", EDGE, COLUMNS, EDGE, SLOPES["s3"]["y0"], EDGE), {
            f"s3_{i}": MEDIUM for i in range(21)}
    if slope == "s2":
        return mtt.brick_layers("s2", "big", 0.2, 0.1, 5, SLOPES["s2"]["y0"]), {
            f"s2_{k}_{i}_0_0": BIG for k in range(5) for i in range(5 - k)}
    if slope == "s4":
        return mtt.brick_layers("s4", "medium", 0.1, 0.1, 6, SLOPES["s4"]["y0"]), {
            f"s4_{k}_{i}_0_0": MEDIUM for k in range(6) for i in range(6 - k)}
    volumes = {f"s5_{i}": SMALL for i in range(80)}
    volumes.update({f"s5_top{k}_{i}_0_0": BIG for k in range(4) for i in range(5 - k)})
    return mtt.slope5(), volumes


def stepped_slope(slope, step, heights):
    """Columns k = 0 (toe) .. n - 1 (back), heights[k] layers, each on a driven tread k b high."""
    width, layer, y0 = (SLOPES[slope][key] for key in ("width", "layer", "y0"))
    shape, volume = ("medium", MEDIUM) if width == EDGE else ("big", BIG)
    n = len(heights)
    text, volumes = "", {}
    for k in range(n):
        x_hi = X0 + width * (n - k)
        x_lo = x_hi - width
        base = k * step
        if k > 0:
            text += f"""
[[shape]]
name = "tread{k}"
type = "box"
min = [{x_lo:g}, {y0 - 0.05:g}, 0]
max = [{x_hi:g}, {y0 + 0.1 + 0.05:g}, {base:g}]

[[particle]]
label = "tread{k}"
shape = "tread{k}"
material = "block"
driver = "tilt"
"""
        for j in range(heights[k]):
            label = f"{slope}_c{k}_{j}"
            volumes[label] = volume
            text += f"""
[[particle]]
label = "{label}"
shape = "{shape}"
material = "block"
position = [{x_lo + 0.5 * width:g}, {y0 + 0.05:g}, {base + (j + 0.5) * layer:g}]
"""
    return text, volumes


def heights_of(slope, base):
    """The columns' heights in layers from the toe up: the staircase's own (1, 2, .., n) on the
    flat and stepped bases, or the base's list."""
    cubes = BASES[base][1]
    if cubes not in (None, "staircase"):
        return cubes
    return list(range(1, (6 if slope == "s3" else 5) + 1))


def wider(text):
    """The blocks toppling off the treads fly past x = 2.5 m: the domain and floor reach 8 m."""
    for old, new in (("max = [2.5, 2, 1.5]", "max = [8, 2, 1.5]"),
                     ("max = [2.5, 2, -1.4]", "max = [8, 2, -1.4]")):
        assert old in text
        text = text.replace(old, new)
    return text


def scene(name):
    """The scene of one case: its text and its blocks' labels with their volumes."""
    slope, base, _, rate = CASES[name]
    step, _ = BASES[base]
    heights = None if base == "flat" else heights_of(slope, base)
    body, volumes = flat_slope(slope) if heights is None else stepped_slope(slope, step, heights)
    text = header(rate, name) + body
    if heights is not None:
        text = wider(text)
    text += "\n[output]\nseries_every = 1000\nmonitor = [" + ", ".join(f'"{x}"' for x in volumes)
    text += "]\n"
    text += mtt.checks(slope, *SLOPES[slope]["reference"])
    return text, volumes


def command(name, scene_file, out):
    kernel = CASES[name][2]
    cmd = ["nice", "-n", "10", "build/bin/polydem", "run", scene_file, "--out", out,
           "--no-snapshots", "--quiet"]
    return cmd + (["--kernel", kernel] if kernel != GJK else [])


def onset_angle(history, size=EDGE):
    """The tilt (deg) from which the fastest block's speed against the platform stays above
    EPS x sqrt(g x size) (size: the slope's smallest block) until a block has moved REACH: the
    start of the motion that fails the slope, not an earlier slip that jams. NaN when no block
    moves REACH."""
    v_min = EPS * math.sqrt(9.81 * size)
    fail = next((i for i, (_, d, _) in enumerate(history) if d >= REACH), None)
    if fail is None:
        return math.nan
    i = fail
    while i > 0 and history[i - 1][2] > v_min:
        i -= 1
    return history[i][0]


def slope_turn(moves):
    """The `tilt_failure` check's mode reading (module/run/motion_checks.cpp): of (displacement,
    turn, volume) of every block when the first has moved REACH, the volume-weighted median turn
    of those that have moved MOVED x REACH."""
    moved = sorted((turn, v) for d, turn, v in moves if d >= MOVED * REACH)
    half = 0.5 * sum(v for _, v in moved)
    total = 0.0
    for turn, v in moved:
        total += v
        if total >= half:
            return turn
    return math.nan


def analyse(name, out, volumes):
    """Onset, 2 mm, 5 cm and the turns of one run from its series.csv and summary.json."""
    slope, _, _, rate = CASES[name]
    labels = list(volumes)
    with open(os.path.join(out, "series.csv")) as f:
        rows = list(csv.DictReader(f))
    ref, first_turn, turn = None, math.nan, math.nan
    history = []   # (tilt deg, largest displacement against the platform, largest speed)
    for r in rows:
        t = float(r["time"])
        if t < mtt.START - 1e-12:
            continue
        th = rate * (t - mtt.START)
        c, s = math.cos(th), math.sin(th)
        # The platform turns by th about y through the origin: undo it.
        pts = []
        for lab in labels:
            x, y, z = (float(r[f"{lab}_{a}"]) for a in "xyz")
            pts.append((c * x - s * z, y, s * x + c * z))
        if ref is None:
            ref = pts
        moves = [math.dist(p, q) for p, q in zip(pts, ref)]
        d = max(moves)
        # Speed against the platform: the block's velocity less the platform's, w x r (w along
        # y, the pivot at the origin).
        v = 0.0
        for lab in labels:
            x, z = float(r[f"{lab}_x"]), float(r[f"{lab}_z"])
            vx, vy, vz = (float(r[f"{lab}_v{a}"]) for a in "xyz")
            v = max(v, math.hypot(vx - rate * z, vy, vz + rate * x))
        history.append((math.degrees(th), d, v))
        if d >= REACH and math.isnan(turn):
            # The blocks turn about y as the platform does: their turn against it is the
            # difference of the angles.
            turns = [abs(math.degrees(float(r[f"{lab}_rotation"]) - th)) for lab in labels]
            first_turn = turns[moves.index(d)]
            turn = slope_turn(zip(moves, turns, volumes.values()))
    onset = onset_angle(history, SLOPES[slope]["L"])
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    checks = {c["name"]: c for c in summary.get("checks", [])}
    angle = checks.get(f"{slope}: failure angle", {}).get("value")
    mode = SLOPES[slope]["reference"][0]
    check_turn = next((c.get("value") for n, c in checks.items()
                       if n.startswith(f"{slope}: {mode} (")), None)
    angle, check_turn = (math.nan if v is None else v for v in (angle, check_turn))
    return {"onset": onset, "angle_2mm": angle, "check_turn": check_turn,
            "first_turn": first_turn, "turn": turn,
            "end_d": history[-1][1] if history else math.nan,
            "reach_angle": next((th for th, d, _ in history if d >= REACH), math.nan)}


def run_case(name, root):
    out = os.path.join(root, name)
    os.makedirs(root, exist_ok=True)
    text, volumes = scene(name)
    scene_file = os.path.join(root, f"{name}.toml")
    with open(scene_file, "w") as f:
        f.write(text)
    cmd = command(name, scene_file, out)
    t0 = time.time()
    subprocess.run(cmd, check=False)
    wall = time.time() - t0
    result = analyse(name, out, volumes)
    result.update(name=name, wall=wall, command=" ".join(cmd))
    with open(os.path.join(root, f"{name}.json"), "w") as f:
        json.dump(result, f, indent=1)
    return result


def gb_set_limit(step, cubes, width=EDGE, layer=EDGE):
    """Goodman and Bray's limit tilt (deg) of columns of `cubes` layers (toe first) `width` wide
    on treads rising `step` m: the platform's tilt at which their recursion
    (tests/apps/goodman_bray.py, mu on bases and sides) first needs a force at a toe. Columns
    whose lower neighbour's top is below their tread stand free of it: each connected run of
    columns is its own set."""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../tests/apps"))
    from goodman_bray import toe_force
    phi = math.degrees(math.atan(mtt.MU))
    heights = [layer * n for n in cubes]
    bases = [k * step for k in range(len(heights))]
    runs = [[0]]
    for k in range(1, len(heights)):
        if bases[k - 1] + heights[k - 1] - bases[k] > 1e-12:
            runs[-1].append(k)
        else:
            runs.append([k])
    limits = []
    for run in runs:
        h, b = [heights[i] for i in run], [bases[i] for i in run]
        lo, hi = 0.01, phi - 1e-6
        for _ in range(80):
            mid = 0.5 * (lo + hi)
            if toe_force(phi, mid, width, h, b)[0] > 0.0:
                hi = mid
            else:
                lo = mid
        limits.append(0.5 * (lo + hi))
    return min(limits)


def limit(slope, base):
    """The rigid-block limit tilt (deg) of a slope on a base, and what gives it: Goodman and
    Bray's for a set of columns, the friction angle atan(mu) (sliding on the platform) for the
    others (C = 2.14 Pa adds under 0.01 deg)."""
    width = SLOPES[slope]["width"]
    if width is None:
        rate = mtt.TILT_RATE
        return math.degrees(math.atan(mtt.MU)), (
            f"sliding, atan(mu); a rigid block reaches 2 mm at {slide_angle(0.002, rate):.2f}")
    step = BASES[base][0]
    return gb_set_limit(step, heights_of(slope, base), width, SLOPES[slope]["layer"]), \
        "Goodman-Bray"


def slide_angle(d, rate):
    """The tilt (deg) at which a rigid block at rest on the platform until the tilt reaches
    atan(mu), then sliding with friction mu while the platform turns at `rate`, has slid d (m):
    x'' = g (sin th - mu cos th), th = atan(mu) + rate t. Near the friction angle
    x = g rate t^3 / (6 cos(atan mu)); integrated here."""
    g, th, x, v, dt = 9.81, math.atan(mtt.MU), 0.0, 0.0, 1e-5
    while x < d:
        v += g * (math.sin(th) - mtt.MU * math.cos(th)) * dt
        x += v * dt
        th += rate * dt
    return math.degrees(th)


def gb_steps():
    """The staircase (6 .. 1 cubes) on treads of every rise: Goodman and Bray's limit tilt."""
    lines = ["| tread rise b (m) | Goodman-Bray limit tilt (deg) |", "|---|---|"]
    for b in (0.0, 0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5):
        lines.append(f"| {b:g} | {gb_set_limit(b, range(1, COLUMNS + 1)):.2f} |")
    return "\n".join(lines) + "\n"


def mode_of(turn):
    return "toppling" if turn > 2.0 else "sliding" if turn >= 0.0 else "-"


def table(root):
    lines = ["| case | slope | base | kernel | tilt rate (rad/s) | onset (deg) | 2 mm (deg) "
             "| 5 cm (deg) | first block's turn at 5 cm (deg) | slope's turn at 5 cm (deg) "
             "| mode | experiment (deg) | rigid limit (deg) | wall (s) | command |",
             "|" + "---|" * 15]
    for name in CASES:
        path = os.path.join(root, f"{name}.json")
        if not os.path.exists(path):
            continue
        with open(path) as f:
            r = json.load(f)
        # Read the run's outputs again: the table follows this file's definitions.
        r.update(analyse(name, os.path.join(root, name), scene(name)[1]))
        slope, base, kernel, rate = CASES[name]
        step = BASES[base][0]
        where = f"{base} (b = {step:g} m)" if base != "flat" else base
        mode, low, high, _ = SLOPES[slope]["reference"]
        lim, what = limit(slope, base)
        lines.append(f"| {name} | {slope} | {where} | {kernel} | {rate:g} | {r['onset']:.2f} "
                     f"| {r['angle_2mm']:.2f} | {r['reach_angle']:.2f} | {r['first_turn']:.1f} "
                     f"| {r['turn']:.1f} | {mode_of(r['turn'])} | {mode} {low}-{high} "
                     f"| {lim:.2f} ({what}) | {r['wall']:.0f} | `{r['command']}` |")
    text = "\n".join(lines) + "\n"
    with open(os.path.join(root, "table.md"), "w") as f:
        f.write(text)
    return text


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", nargs="*", default=[], help=f"'all' or some of {list(CASES)}")
    ap.add_argument("--out", default="results/tilt-study")
    ap.add_argument("--table", help="only write the table of the runs under this folder")
    ap.add_argument("--goodman-bray", action="store_true",
                    help="only print the staircase's limit tilt against the treads' rise")
    args = ap.parse_args()
    if args.goodman_bray:
        print(gb_steps(), end="")
        return
    if args.table:
        print(table(args.table), end="")
        return
    names = list(CASES) if args.cases == ["all"] else args.cases
    for name in names:
        if name not in CASES:
            sys.exit(f"tilt_study.py: unknown case '{name}' (known: {', '.join(CASES)})")
    for name in names:
        r = run_case(name, args.out)
        print(f"{name}: onset {r['onset']:.2f} deg, 2 mm {r['angle_2mm']:.2f} deg, "
              f"5 cm {r['reach_angle']:.2f} deg, slope's turn {r['turn']:.1f} deg, "
              f"{r['wall']:.0f} s", flush=True)
    print(table(args.out), end="")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""A-TILT-TABLE's toppling staircase (slope 3: six columns of 0.1 m cubes, 6 .. 1 high) run alone,
on the flat platform as in the benchmark or on a stepped base, with a chosen contact kernel and
tilt rate; reports the failure onset and the 2 mm angle of each run (docs/validation.md,
"A-TILT-TABLE: onset, 2 mm, kernel, base and rate").

Every variant keeps A-TILT-TABLE's materials, platform, floor, settling time and end angle
(28 deg; make_tilt_table.HEADER), and slope 3's own checks. Only slope 3 stands on the platform,
and its blocks are monitored, so that series.csv holds their history.

  flat:     slope 3 exactly as in A-TILT-TABLE (a rock mass cut into 21 cubes).
  stepped:  the same six columns, each standing on its own tread, Goodman and Bray's geometry: the
            tread under the k-th column from the toe is k b above the platform (b = 0.05 m, half
            a cube; BASES below), a box turning with the platform. A column's face is then pressed by its lower
            neighbour only above that neighbour's tread. The domain and the floor that catches
            the fallen blocks reach 8 m down the tilt instead of 2.5 m.
  columns5: six columns of 5 cubes each on treads rising b = 0.1 m (one cube): Goodman and Bray's
            regular set, a staircase too, whose limit is that of one column, atan(1 / 5).

Angles (from series.csv, every 1000 steps): d(t) is the largest displacement of a slope-3 block
against the platform since the tilt started (t = 0.5 s, blocks settled), v(t) the largest speed
of a block against the platform. Failure: d reaches REACH = 5 cm (half a block). Onset (scale-
free): the tilt from which v stays above EPS sqrt(g L) (1e-3 x 0.99 m/s = 1 mm/s for L = 0.1 m)
until that failure: the first sustained motion (a slip that jams again, v falling back, is not
one). 2 mm: the benchmark's `tilt_failure` check (the first block to move 2 mm, jam or not). The mode is read when a block has first moved 5 cm: the turn
against the platform of that block (the benchmark's check) and the median turn of all 21 blocks;
toppling when the median turn is above 2 deg. The two differ when the block that moved first is
the top cube of a leaning column sliding off it.

Run from the repository root, one case after another (each at full length, 1 rank, nice -n 10):
  /usr/bin/python3 benchmark_scenes/tools/tilt_study.py --cases all --out results/tilt-study
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
COLUMNS = 6           # back column 6 cubes high, toe column 1
X0, Y0 = 0.0, 0.6     # slope 3's back corner on the platform (as in A-TILT-TABLE)
# Each base: the rise b of each tread over the next lower one (m) and the columns' heights in
# cubes from the toe up (None: slope 3 as in A-TILT-TABLE, on the flat platform).
BASES = {
    "flat": (0.0, None),
    "stepped": (0.05, [1, 2, 3, 4, 5, 6]),
    "columns5": (0.1, [5] * COLUMNS),
}
REACH = 0.05          # m: the mode is read when a block has moved this far (as the check)
EPS = 1e-3            # onset: sustained speed against the platform, as a fraction of sqrt(g L)
END_ANGLE = 28.0      # deg, as A-TILT-TABLE
CASES = {             # name: (base, kernel, tilt rate rad/s)
    "flat-gjk-0.03": ("flat", "gjk-epa-ipm", 0.03),
    "flat-gjk-0.06": ("flat", "gjk-epa-ipm", 0.06),
    "stepped-gjk-0.03": ("stepped", "gjk-epa-ipm", 0.03),
    "stepped-gjk-0.06": ("stepped", "gjk-epa-ipm", 0.06),
    "flat-dp-0.03": ("flat", "distance-potential", 0.03),
    "stepped-dp-0.03": ("stepped", "distance-potential", 0.03),
    "flat-dp-0.06": ("flat", "distance-potential", 0.06),
    "stepped-dp-0.06": ("stepped", "distance-potential", 0.06),
    "columns5-gjk-0.03": ("columns5", "gjk-epa-ipm", 0.03),
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


def flat_slope():
    return mtt.rock_mass("s3", EDGE, COLUMNS, EDGE, Y0, EDGE), [f"s3_{i}" for i in range(21)]


def stepped_slope(step, heights):
    """Columns k = 0 (toe) .. 5 (back), heights[k] cubes, each on a driven tread k b high."""
    text, labels = "", []
    for k in range(COLUMNS):
        x_hi = X0 + EDGE * (COLUMNS - k)
        x_lo = x_hi - EDGE
        base = k * step
        if k > 0:
            text += f"""
[[shape]]
name = "tread{k}"
type = "box"
min = [{x_lo:g}, {Y0 - 0.05:g}, 0]
max = [{x_hi:g}, {Y0 + EDGE + 0.05:g}, {base:g}]

[[particle]]
label = "tread{k}"
shape = "tread{k}"
material = "block"
driver = "tilt"
"""
        for j in range(heights[k]):
            label = f"s3_c{k}_{j}"
            labels.append(label)
            text += f"""
[[particle]]
label = "{label}"
shape = "medium"
material = "block"
position = [{x_lo + 0.5 * EDGE:g}, {Y0 + 0.5 * EDGE:g}, {base + (j + 0.5) * EDGE:g}]
"""
    return text, labels


def wider(text):
    """The blocks toppling off the treads fly past x = 2.5 m: the domain and floor reach 8 m."""
    for old, new in (("max = [2.5, 2, 1.5]", "max = [8, 2, 1.5]"),
                     ("max = [2.5, 2, -1.4]", "max = [8, 2, -1.4]")):
        assert old in text
        text = text.replace(old, new)
    return text


def scene(name):
    base, _, rate = CASES[name]
    step, heights = BASES[base]
    slope, labels = flat_slope() if heights is None else stepped_slope(step, heights)
    text = header(rate, name) + slope
    if heights is not None:
        text = wider(text)
    text += "\n[output]\nseries_every = 1000\nmonitor = [" + ", ".join(f'"{x}"' for x in labels)
    text += "]\n"
    text += mtt.checks("s3", "toppling", 9.8, 11.6, "toppling 11 deg; Li: 10.0")
    return text, labels


def command(name, scene_file, out):
    kernel = CASES[name][1]
    cmd = ["nice", "-n", "10", "build/bin/polydem", "run", scene_file, "--out", out,
           "--no-snapshots", "--quiet"]
    return cmd + (["--kernel", kernel] if kernel != "gjk-epa-ipm" else [])


def onset_angle(history):
    """The tilt (deg) from which the fastest block's speed against the platform stays above
    EPS x sqrt(g x block size) until a block has moved REACH: the start of the motion that fails
    the slope, not an earlier slip that jams. NaN when no block moves REACH."""
    v_min = EPS * math.sqrt(9.81 * EDGE)
    fail = next((i for i, (_, d, _) in enumerate(history) if d >= REACH), None)
    if fail is None:
        return math.nan
    i = fail
    while i > 0 and history[i - 1][2] > v_min:
        i -= 1
    return history[i][0]


def analyse(name, out, labels):
    """Onset, 2 mm angle and mode of one run from its series.csv and summary.json."""
    rate = CASES[name][2]
    with open(os.path.join(out, "series.csv")) as f:
        rows = list(csv.DictReader(f))
    ref, median_turn = None, None
    history = []   # (tilt deg, largest displacement against the platform)
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
        d = max(math.dist(p, q) for p, q in zip(pts, ref))
        # Speed against the platform: the block's velocity less the platform's, w x r (w along
        # y, the pivot at the origin).
        v = 0.0
        for lab in labels:
            x, z = float(r[f"{lab}_x"]), float(r[f"{lab}_z"])
            vx, vy, vz = (float(r[f"{lab}_v{a}"]) for a in "xyz")
            v = max(v, math.hypot(vx - rate * z, vy, vz + rate * x))
        history.append((math.degrees(th), d, v))
        if d >= REACH and median_turn is None:
            # The blocks turn about y as the platform does: their turn against it is the
            # difference of the angles.
            turns = sorted(abs(math.degrees(float(r[f"{lab}_rotation"]) - th)) for lab in labels)
            median_turn = turns[len(turns) // 2]
    onset = onset_angle(history)
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    checks = {c["name"]: c for c in summary.get("checks", [])}
    angle = checks.get("s3: failure angle", {}).get("value")
    turn = checks.get("s3: toppling (block turn when it has moved 5 cm)", {}).get("value")
    angle, turn = (math.nan if v is None else v for v in (angle, turn))
    return {"onset": onset, "angle_2mm": angle, "turn": turn,
            "median_turn": math.nan if median_turn is None else median_turn,
            "end_d": history[-1][1] if history else math.nan,
            "reach_angle": next((th for th, d, _ in history if d >= REACH), math.nan)}


def run_case(name, root):
    out = os.path.join(root, name)
    os.makedirs(root, exist_ok=True)
    text, labels = scene(name)
    scene_file = os.path.join(root, f"{name}.toml")
    with open(scene_file, "w") as f:
        f.write(text)
    cmd = command(name, scene_file, out)
    t0 = time.time()
    subprocess.run(cmd, check=False)
    wall = time.time() - t0
    result = analyse(name, out, labels)
    result.update(name=name, wall=wall, command=" ".join(cmd))
    with open(os.path.join(root, f"{name}.json"), "w") as f:
        json.dump(result, f, indent=1)
    return result


def gb_set_limit(step, cubes):
    """Goodman and Bray's limit tilt (deg) of six columns of `cubes` cubes (toe first) on treads
    rising `step` m: the platform's tilt at which their recursion (tests/apps/goodman_bray.py,
    mu on bases and sides) first needs a force at a toe. Columns whose lower neighbour's top is
    below their tread stand free of it: each connected run of columns is its own set."""
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../tests/apps"))
    from goodman_bray import toe_force
    phi = math.degrees(math.atan(mtt.MU))
    heights = [EDGE * n for n in cubes]
    bases = [k * step for k in range(COLUMNS)]
    runs = [[0]]
    for k in range(1, COLUMNS):
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
            if toe_force(phi, mid, EDGE, h, b)[0] > 0.0:
                hi = mid
            else:
                lo = mid
        limits.append(0.5 * (lo + hi))
    return min(limits)


def gb_limit(base):
    """Goodman and Bray's limit tilt (deg) of the six columns on that base."""
    step, cubes = BASES[base]
    return gb_set_limit(step, cubes or range(1, COLUMNS + 1))


def gb_steps():
    """The staircase (6 .. 1 cubes) on treads of every rise: Goodman and Bray's limit tilt."""
    lines = ["| tread rise b (m) | Goodman-Bray limit tilt (deg) |", "|---|---|"]
    for b in (0.0, 0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5):
        lines.append(f"| {b:g} | {gb_set_limit(b, range(1, COLUMNS + 1)):.2f} |")
    return "\n".join(lines) + "\n"


def table(root):
    lines = ["| case | base | kernel | tilt rate (rad/s) | onset (deg) | 2 mm (deg) | 5 cm (deg) "
             "| turn at 5 cm (deg) "
             "| median turn at 5 cm (deg) | mode | Goodman-Bray limit (deg) | wall (s) | command |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for name in CASES:
        path = os.path.join(root, f"{name}.json")
        if not os.path.exists(path):
            continue
        with open(path) as f:
            r = json.load(f)
        # Read the run's outputs again: the table follows this file's definitions.
        r.update(analyse(name, os.path.join(root, name), scene(name)[1]))
        base, kernel, rate = CASES[name]
        m = r.get("median_turn", math.nan)
        mode = "toppling" if m > 2.0 else "sliding" if m >= 0.0 else "-"
        step, cubes = BASES[base]
        where = f"{base} (b = {step:g} m)" if cubes else base
        lines.append(f"| {name} | {where} "
                     f"| {kernel} | {rate:g} | {r['onset']:.2f} | {r['angle_2mm']:.2f} "
                     f"| {r['reach_angle']:.2f} "
                     f"| {r['turn']:.1f} | {m:.1f} | {mode} | {gb_limit(base):.2f} | {r['wall']:.0f} "
                     f"| `{r['command']}` |")
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
              f"turn {r['turn']:.1f} deg, {r['wall']:.0f} s", flush=True)
    print(table(args.out), end="")


if __name__ == "__main__":
    main()

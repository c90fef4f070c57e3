#!/usr/bin/python3
"""Friction sweep of Keissar's quasi-2D slice model (benchmark_scenes/A-SLICES-2D.toml; thesis
section 4.4, figs. 4.4 and 4.5): runs the scene for each pair of base and inter-slice friction
angles, classifies each run's mode from the blocks' measured motion and prints a table.

    /usr/bin/python3 benchmark_scenes/tools/slices_sweep.py POLYDEM SCENE OUTDIR
        [--cases fig45 | fig44 | grid] [--case BASE/SLICES ...] [--jobs N] [--resume] [--snapshots]
        [--check]

--cases fig45: the three cases of fig. 4.5 (45/45 halts, 5/45 slides, 45/25 topples);
fig44: inter-slice friction 20, 25, 27.5, 30, 32.5, 35, 40, 45 deg with the base at 45 deg
(fig. 4.4); grid (default): base 5, 15, 25, 45 x inter-slice 25, 35, 45 and the line of
fig44. --check exits 1 when a case the thesis names has another mode, or when the toppling of
fig. 4.4 does not end between 25 and 35 deg of inter-slice friction (the thesis: below about
30 deg).

Each run writes the scene with the joints' friction angles replaced (the [[joint]]s "base" and
"slices", and the material's, which corner and edge contacts between slices take) into
OUTDIR/b<base>_s<slices>/, runs it to the scene's end_time and reads series.csv (the scene
monitors every block of the rock mass; the script checks the count against polydem's report).
The mode, with t the slice thickness (the "slices" joint set's spacing), from the centroids'
displacements d and rotation angles of the blocks:

- halts: at the end every block is at rest (speed below 1e-3 sqrt(g t), 6 mm/s for t = 4 m)
  and none has moved by more than t: the mass came to a halt after "a little displacement"
  (the thesis's halting mass slides on the back fault first, fig. 4.5a);
- otherwise the mode is read at the first output row where some block's centroid has moved by
  more than t / 4, from the turning share of each block that has moved at least a tenth as
  much as the one that moved most: its rotation angle x the height of its centroid above the
  failure surface beneath it (the highest of the planes that fix the rock below them) over its
  displacement. A slice turning about its toe has a share near 1, one that slides without
  turning near 0. topples: some block's share is above 0.5; slides: none;
- undecided: neither at rest nor moved by t / 4 (too short a run).

All thresholds are ratios: displacements to the slice thickness, turning to displacement.
The table gives for every run the figures behind its mode, so that the margin of each call
can be seen.
"""
import argparse
import concurrent.futures
import csv
import math
import pathlib
import re
import subprocess
import sys
import tomllib

MOVE_FRACTION = 0.25   # a block has moved: its centroid by t / 4
REST_FRACTION = 1e-3   # at rest: speed below this x sqrt(g t)
HALT_FRACTION = 1.0    # halts: at rest at the end, no block moved by more than this x t
TOPPLE_SHARE = 0.5     # topples: turning gave a block half or more of its displacement

GRID_BASE = [5, 15, 25, 45]
GRID_SLICES = [25, 35, 45]
FIG45 = {(45, 45): "halts", (5, 45): "slides", (45, 25): "topples"}
FIG44_SLICES = [20, 25, 27.5, 30, 32.5, 35, 40, 45]


def set_friction(text, table, name, value):
    """Replaces friction_angle in the [[table]] whose name is `name`."""
    out, current, name_of = [], None, None
    lines = text.splitlines(keepends=True)
    found = False
    for line in lines:
        head = re.match(r"\s*\[\[?([^\]]+)\]\]?", line)
        if head:
            current, name_of = head.group(1).strip(), None
        m = re.match(r'\s*name\s*=\s*"([^"]*)"', line)
        if m:
            name_of = m.group(1)
        if current == table and name_of == name and re.match(r"\s*friction_angle\s*=", line):
            line = f"friction_angle = {value}\n"
            found = True
        out.append(line)
    if not found:
        sys.exit(f"error: no friction_angle in [[{table}]] '{name}' after its name")
    return "".join(out)


def read_series(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return [{k: float(v) for k, v in r.items()} for r in rows]


def surface_height(planes, x, y):
    """Height of the failure surface under (x, y): the highest of the rock mass's planes that fix
    the rock below them (the base and the back fault)."""
    best = -math.inf
    for p in planes:
        d, dd = math.radians(p["dip"]), math.radians(p["dip_direction"])
        n = (math.sin(d) * math.sin(dd), math.sin(d) * math.cos(dd), math.cos(d))
        x0, y0, z0 = p["point"]
        best = max(best, z0 - (n[0] * (x - x0) + n[1] * (y - y0)) / n[2])
    return best


def classify(rows, labels, planes, t, g):
    """The mode from the blocks' motion (see the module's docstring) and the figures behind it."""
    first = rows[0]
    start = {b: (first[b + "_x"], first[b + "_z"]) for b in labels}
    # Lever arm of each block: its centroid's height above the failure surface beneath it.
    arm = {b: first[b + "_z"] - surface_height(planes, first[b + "_x"], first[b + "_y"])
           for b in labels}

    def disp(r, b):
        return math.dist((r[b + "_x"], r[b + "_z"]), start[b])

    moved_at, max_disp, max_drift = None, 0.0, 0.0
    for r in rows:
        for b in labels:
            d = disp(r, b)
            max_disp = max(max_disp, d)
            max_drift = max(max_drift, abs(r[b + "_y"] - first[b + "_y"]))
            if moved_at is None and d > MOVE_FRACTION * t:
                moved_at = r
    last = rows[-1]
    end_speed = max(math.sqrt(last[b + "_vx"] ** 2 + last[b + "_vy"] ** 2 + last[b + "_vz"] ** 2)
                    for b in labels)
    figures = {"max_disp": max_disp, "end_speed": end_speed, "y_drift": max_drift}
    at = moved_at or last
    figures["turn_deg"] = max(math.degrees(abs(at[b + "_rotation"])) for b in labels)
    # Turning share of each block that moved at least a tenth as much as the one that moved most:
    # the displacement its turn about its base gives its centroid over the displacement it had.
    most = max(disp(at, b) for b in labels)
    shares = [abs(at[b + "_rotation"]) * arm[b] / disp(at, b) for b in labels
              if most > 0 and disp(at, b) >= 0.1 * most]
    figures["turn_share"] = max(shares) if shares else 0.0
    rest = end_speed < REST_FRACTION * math.sqrt(g * t)
    if rest and max_disp < HALT_FRACTION * t:
        return "halts", figures
    if moved_at is None:
        return "undecided", figures
    figures["decided_at"] = moved_at["time"]
    return ("topples" if figures["turn_share"] > TOPPLE_SHARE else "slides"), figures


def same_scene(a, b):
    """The two scene texts describe the same run: equal but for comments and [scene]."""
    x, y = tomllib.loads(a), tomllib.loads(b)
    x.pop("scene", None)
    y.pop("scene", None)
    return x == y


def run_case(polydem, scene_text, labels, out, base, slices, snapshots, resume):
    """Runs one pair of friction angles; returns series.csv's rows and polydem's wall time (s)."""
    text = set_friction(scene_text, "joint", "base", base)
    text = set_friction(text, "joint", "slices", slices)
    text = set_friction(text, "material", "rock", slices)
    case = out / f"b{base:g}_s{slices:g}"
    case.mkdir(parents=True, exist_ok=True)
    path = case / "scene.toml"
    log = case / "log.txt"
    # A run counts when it reached the scene's end time (a stop by a signal also exits 0).
    finished = re.compile(r"^finished: end time after .*, ([0-9.e+-]+) s wall$", re.M)
    # --resume: a finished run of the same scene (its comments and [scene] titles aside) is taken
    # as it is; the runs are deterministic, so a sweep stopped half way gives the same table.
    done = (resume and path.exists() and same_scene(path.read_text(), text) and log.exists()
            and finished.search(log.read_text()) and (case / "run" / "series.csv").exists())
    if not done:
        path.write_text(text)
        with open(log, "w") as f:
            cmd = [polydem, "run", str(path), "--out", str(case / "run")]
            rc = subprocess.run(cmd + ([] if snapshots else ["--no-snapshots"]), stdout=f,
                                stderr=subprocess.STDOUT).returncode
        if rc != 0:
            raise RuntimeError(f"polydem failed on {path} (exit {rc}); see {log}")
        if not finished.search(log.read_text()):
            raise RuntimeError(f"polydem stopped before the end time on {path}; see {log}")
    # Every block must be watched: the rock mass's report gives how many there are.
    m = re.search(r"(\d+) free and (\d+) fixed blocks", log.read_text())
    if not m or int(m.group(1)) + int(m.group(2)) != len(labels):
        raise RuntimeError(f"{path}: [output] monitor lists {len(labels)} labels, the rock mass "
                           f"has {m.group(0) if m else 'an unknown number of blocks'}")
    return read_series(case / "run" / "series.csv"), float(finished.search(log.read_text())[1])


def thesis_mode(base, slices):
    """The mode the thesis gives (fig. 4.5; fig. 4.4 for base 45 deg), "" where it gives none."""
    if (base, slices) in FIG45:
        return FIG45[(base, slices)]
    if base == 45 and slices != 30:
        return "topples" if slices < 30 else "halts"
    return ""


def sweep(a, cases, scene_text, labels, planes, t, g):
    """Runs the cases, --jobs at a time, prints a row per run in order; returns their modes."""
    modes = {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as pool:
        runs = [pool.submit(run_case, a.polydem, scene_text, labels, pathlib.Path(a.out), b, s,
                             a.snapshots, a.resume)
                for b, s in cases]
        for (base, slices), run in zip(cases, runs):
            rows, wall = run.result()
            mode, f = classify(rows, labels, planes, t, g)
            modes[(base, slices)] = mode
            print(f"| {base:g} | {slices:g} | {mode} | {thesis_mode(base, slices)} | "
                  f"{f['max_disp']:.3g} | {f['turn_deg']:.3g} | {f['turn_share']:.2f} | "
                  f"{format(f['decided_at'], '.3g') if 'decided_at' in f else '-'} | "
                  f"{f['end_speed']:.2g} | "
                  f"{f['y_drift']:.2g} | {wall:.0f} |", flush=True)
    return modes


def compare(modes):
    """What differs from the thesis: the cases of fig. 4.5, and where toppling ends at base 45."""
    failures = [f"{b:g}/{s:g}: {modes[(b, s)]}, the thesis {m}" for (b, s), m in FIG45.items()
                if (b, s) in modes and modes[(b, s)] != m]
    line = sorted((s, m) for (b, s), m in modes.items() if b == 45)
    if len(line) > 2:
        topples = [s for s, m in line if m == "topples"]
        stands = [s for s, m in line if m == "halts"]
        if (topples and stands and len(topples) + len(stands) == len(line)
                and max(topples) < min(stands)):
            print(f"base 45 deg: topples up to {max(topples):g} deg of inter-slice friction, "
                  f"halts from {min(stands):g} deg on (thesis: topples below about 30 deg)")
            if not (25 <= max(topples) and min(stands) <= 35):
                failures.append(f"toppling ends between {max(topples):g} and {min(stands):g} deg")
        else:
            failures.append(f"not one change from toppling to halting at base 45 deg: {line}")
    return failures


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("polydem")
    ap.add_argument("scene")
    ap.add_argument("out")
    ap.add_argument("--cases", choices=["fig45", "fig44", "grid"], default="grid")
    ap.add_argument("--case", action="append", default=[], metavar="BASE/SLICES",
                    help="run these pairs of friction angles (deg) instead of --cases")
    ap.add_argument("--jobs", type=int, default=1, help="runs at a time (default 1)")
    ap.add_argument("--resume", action="store_true",
                    help="take the finished runs of the same scenes in OUTDIR as they are")
    ap.add_argument("--snapshots", action="store_true",
                    help="keep the runs' snapshots (for plot_slices.py)")
    ap.add_argument("--check", action="store_true",
                    help="exit 1 when a mode differs from the thesis")
    a = ap.parse_args()

    scene_text = pathlib.Path(a.scene).read_text()
    scene = tomllib.loads(scene_text)
    labels = scene["output"]["monitor"]
    sets = [s for m in scene["rock_mass"] for s in m.get("joint_set", [])
            if s.get("joint") == "slices"]
    t = float(str(sets[0]["spacing"]).split()[0])
    planes = [p for m in scene["rock_mass"] for p in m.get("plane", [])
              if p.get("fixed") == "below"]
    g = math.sqrt(sum(c * c for c in scene["simulation"].get("gravity", [0, 0, -9.81])))

    if a.case:
        cases = [tuple(float(v) for v in c.split("/")) for c in a.case]
    elif a.cases == "fig45":
        cases = list(FIG45)
    elif a.cases == "fig44":
        cases = [(45, s) for s in FIG44_SLICES]
    else:
        cases = sorted({(b, s) for b in GRID_BASE for s in GRID_SLICES}
                       | {(45, s) for s in FIG44_SLICES})

    print(f"slice thickness t = {t:g} m; moved: > {MOVE_FRACTION * t:g} m; at rest: < "
          f"{REST_FRACTION * math.sqrt(g * t):.3g} m/s; topples: turning share > {TOPPLE_SHARE:g}")
    print("| base deg | inter-slice deg | mode | thesis | largest displacement m | "
          "largest turn deg | turning share | decided at s | speed at end m/s | y drift m | "
          "wall s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    try:
        modes = sweep(a, cases, scene_text, labels, planes, t, g)
    except RuntimeError as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    failures = compare(modes)
    if failures:
        print("not as the thesis: " + "; ".join(failures))
    return 1 if a.check and failures else 0


if __name__ == "__main__":
    sys.exit(main())

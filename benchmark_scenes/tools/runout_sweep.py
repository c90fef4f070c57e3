#!/usr/bin/python3
"""The friction sweep of A-RUNOUT, as Keissar fig. 4.11, run with `polydem runout`: for each
friction angle (the same on the joints, the faults and the floor) the rock mass is released and
run until at rest (or the time cap), and its runout and deposit measured.

    nice -n 10 /usr/bin/python3 benchmark_scenes/tools/runout_sweep.py \\
        [--angles 10 15 20 25] [--time-cap 60] [--out results/runout-sweep] \\
        [--figure docs/images/a-runout-friction-sweep.png] [--table docs/validation.md]

The cases run one after another (each `polydem runout` on one rank); after each, OUT/sweep.json,
the figure (left: mean displacement of the free blocks against time, one line per angle, as
fig. 4.11; right: runout distance and largest block travel against the friction angle) and the
table (markdown: per angle, at rest or not and when, runout, largest travel, the deposit's
area, length, width and largest thickness, wall time) are rewritten, so that a sweep stopped
part way leaves the cases it finished. A case whose OUT/phi-X/runout.json exists is read, not
run again, unless a signal stopped it (SIGTERM to its polydem): then it is continued from its
OUT/phi-X/runout.h5, as is a case killed without one, so that a sweep to rest can be spread over
several sessions. Each case runs until every block is at rest or the time cap (A-RUNOUT's
end_time, 60 s of run-on, by default); the table gives the mean speed at the end beside Keissar's
rest criterion (1e-4 m/s). The thesis's finding, checked and
reported: the lower the friction, the farther the mass runs out. Exit status 1 if the runout does not fall as the angle rises.
"""
import argparse
import csv
import json
import os
import re
import subprocess
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, os.pardir, os.pardir)
SCENE = os.path.join(HERE, os.pardir, "A-RUNOUT.toml")


def scene_with_angle(text, angle):
    out, n = re.subn(r"friction_angle = [0-9.]+(\s+# sweep)", f"friction_angle = {angle}\\1", text)
    if n == 0:
        raise SystemExit("runout_sweep: no 'friction_angle = ...  # sweep' line in the scene")
    return out


def read_series(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return [float(r["time"]) for r in rows], [float(r["mean_displacement"]) for r in rows]


def run_case(polydem, text, angle, out, time_cap):
    """One angle: its runout.json (run unless already there) and wall seconds (None if read)."""
    run_dir = os.path.join(out, f"phi-{angle:g}")
    result = os.path.join(run_dir, "runout.json")
    checkpoint = os.path.join(run_dir, "runout.h5")
    stopped = None
    if os.path.exists(result):
        with open(result) as f:
            stopped = json.load(f)
        if stopped["stopped_by"] in ("rest", "time_cap") or not os.path.exists(checkpoint):
            return stopped, None
    if os.path.exists(checkpoint) and (stopped is not None or not os.path.exists(result)):
        # Stopped by a signal (or killed): continued from its checkpoint, the same bits as a run
        # that never stopped; the wall time adds up over the parts.
        t0 = time.time()
        cmd = [polydem, "runout", "--resume", run_dir, "--quiet"]
        if time_cap:
            cmd += ["--time-cap", str(time_cap)]
        subprocess.run(cmd, check=True)
        with open(result) as f:
            r = json.load(f)
        return r, (stopped or {}).get("wall_seconds", 0) + time.time() - t0
    os.makedirs(out, exist_ok=True)
    scene = os.path.join(out, f"A-RUNOUT-phi-{angle:g}.toml")
    with open(scene, "w") as f:
        f.write(scene_with_angle(text, angle))
    cmd = [polydem, "runout", scene, "--out", run_dir, "--check-every", "500", "--quiet"]
    if time_cap:
        cmd += ["--time-cap", str(time_cap)]
    t0 = time.time()
    subprocess.run(cmd, check=True)
    with open(result) as f:
        return json.load(f), time.time() - t0


BEGIN, END = "<!-- runout_sweep.py table -->", "<!-- /runout_sweep.py table -->"


def write_table(path, table):
    """The table into `path`: between its BEGIN and END markers when it has them (a page of the
    docs keeps its text), else the whole file."""
    text = open(path).read() if os.path.exists(path) else ""
    if BEGIN in text and END in text:
        head, rest = text.split(BEGIN, 1)
        text = head + BEGIN + "\n" + table + END + rest.split(END, 1)[1]
    else:
        text = table
    with open(path, "w") as f:
        f.write(text)


def rest_word(case):
    """The table's "at rest" cell: yes, or why not."""
    if case["at_rest"]:
        return "yes"
    if case["stopped_by"] == "time_cap":
        return "no (time cap; the mass stands)" if case["failed_blocks"] == 0 else "no (time cap)"
    return f"no ({case['stopped_by']}; continued from its checkpoint by the next sweep)"


def final_mean_speed(out, case):
    """The free blocks' mean speed at the last check (Keissar's rest criterion: below 1e-4 m/s)."""
    with open(os.path.join(out, f"phi-{case['friction_angle_deg']:g}", "runout_series.csv")) as f:
        rows = list(csv.DictReader(f))
    return float(rows[-1]["mean_speed"]) if rows else float("nan")


def write_outputs(a, cases):
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.5))
    for c in cases:
        t, d = read_series(os.path.join(a.out, f"phi-{c['friction_angle_deg']:g}",
                                        "runout_series.csv"))
        ax.plot(t, d, label=f"{c['friction_angle_deg']:g} deg"
                + ("" if c["at_rest"] else " (not at rest)"))
    ax.set_xlabel("time [s]")
    ax.set_ylabel("mean displacement of the free blocks [m]")
    ax.set_title("A-RUNOUT friction sweep (cf. Keissar fig. 4.11)", fontsize=10)
    ax.legend(title="friction angle", fontsize=8)
    ax.grid(alpha=0.3)
    phi = [c["friction_angle_deg"] for c in cases]
    bx.plot(phi, [c["runout_distance"] for c in cases], "o-", label="runout of the front")
    bx.plot(phi, [c["largest_block_travel"] for c in cases], "s--", label="largest block travel")
    bx.set_xlabel("friction angle [deg]")
    bx.set_ylabel("m")
    bx.set_title("polydem runout: distance against friction", fontsize=10)
    bx.legend(fontsize=8)
    bx.grid(alpha=0.3)
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(a.figure)), exist_ok=True)
    fig.savefig(a.figure, dpi=110)
    plt.close(fig)
    lines = ["| friction angle (deg) | at rest | run-on time (s) | runout (m) | largest block "
             "travel (m) | failed blocks | deposit area (m^2) | length x width (m) | largest "
             "thickness (m) | mean speed at the end (m/s) | wall time (s) |", "|---" * 11 + "|"]
    for c in cases:
        d = c["deposit"]
        lines.append(
            f"| {c['friction_angle_deg']:g} | {rest_word(c)} | "
            f"{c['time']:.3g} | {c['runout_distance']:.3g} | {c['largest_block_travel']:.3g} | "
            f"{c['failed_blocks']} of {c['free_blocks']} | {d['area']:.4g} | "
            f"{d['length']:.3g} x {d['width']:.3g} | {d['max_thickness']:.3g} | "
            f"{final_mean_speed(a.out, c):.2g} | {c.get('wall_seconds') or 0:.0f} |")
    write_table(a.table, "\n".join(lines) + "\n")
    falls = all(x["runout_distance"] >= y["runout_distance"] for x, y in zip(cases, cases[1:]))
    with open(os.path.join(a.out, "sweep.json"), "w") as f:
        json.dump({"scene": a.scene, "cases": cases, "runout_falls_with_friction": falls}, f,
                  indent=2)
    return falls


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--angles", nargs="+", type=float, default=[10, 15, 20, 25])
    ap.add_argument("--time-cap", type=float, default=60,
                    help="s of run-on at most (default 60, A-RUNOUT's end_time); a case "
                         "stopped by a signal is continued up to this cap")
    ap.add_argument("--scene", default=SCENE)
    ap.add_argument("--polydem", default=os.path.join(ROOT, "build", "bin", "polydem"))
    ap.add_argument("--out", default="results/runout-sweep")
    ap.add_argument("--figure", default=os.path.join(ROOT, "docs", "images",
                                                     "a-runout-friction-sweep.png"))
    ap.add_argument("--table", default=None,
                    help="markdown (default OUT/sweep.md); a file with the markers "
                         f"{BEGIN} ... {END} (docs/validation.md) gets the table between them")
    a = ap.parse_args()
    a.table = a.table or os.path.join(a.out, "sweep.md")
    text = open(a.scene).read()
    cases = []
    # The stiffest (soonest at rest) first: a sweep cut short keeps the most cases.
    for angle in sorted(a.angles, reverse=True):
        r, wall = run_case(a.polydem, text, angle, a.out, a.time_cap)
        case = dict(r, friction_angle_deg=angle)
        case["wall_seconds"] = wall if wall is not None else r.get("wall_seconds")
        with open(os.path.join(a.out, f"phi-{angle:g}", "runout.json"), "w") as f:
            json.dump(case, f, indent=2)
        cases.append(case)
        cases.sort(key=lambda c: c["friction_angle_deg"])
        print(f"phi {angle:5g} deg: runout {r['runout_distance']:.3g} m, largest travel "
              f"{r['largest_block_travel']:.3g} m, {'at rest' if r['at_rest'] else 'NOT at rest'}"
              f" after {r['time']:.3g} s", flush=True)
        falls = write_outputs(a, cases)
    print(f"wrote {a.figure}, {a.table}, {a.out}/sweep.json; runout falls as friction rises: {falls}")
    return 0 if falls else 1


if __name__ == "__main__":
    sys.exit(main())

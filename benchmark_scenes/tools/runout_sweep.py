#!/usr/bin/python3
"""The friction sweep of A-RUNOUT, as Keissar fig. 4.11: the mean displacement of the rock mass
against time for several friction angles (the same angle on the joints, the faults and the floor).

    PYTHONPATH=build/python /usr/bin/python3 benchmark_scenes/tools/runout_sweep.py \\
        [--angles 10 12.5 15 20 25] [--end-time 40] [--out results/runout-sweep]

Runs each angle with polydem.run (the scene's lines marked "# sweep" get the angle), then writes
OUT/sweep.png (mean displacement against time, one line per angle), OUT/sweep.json (per angle:
final mean displacement, runout of the front, mean speed at the end, whether the mass came to
rest) and OUT/<angle>/ (each run's summary.json and series.csv). The thesis's finding, which the
script checks and reports: the lower the friction, the farther the mass moves; above the limit it
moves a little and stops, below it it keeps accelerating. Exit status 1 if the final mean
displacements do not fall as the angle rises.
"""
import argparse
import csv
import json
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import polydem  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, os.pardir, "A-RUNOUT.toml")


def scene_with_angle(text, angle):
    out, n = re.subn(r"friction_angle = [0-9.]+(\s+# sweep)", f"friction_angle = {angle}\\1", text)
    if n == 0:
        raise SystemExit("runout_sweep: no 'friction_angle = ...  # sweep' line in the scene")
    return out


def read_series(path, column):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return [float(r["time"]) for r in rows], [float(r[column]) for r in rows]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--angles", nargs="+", type=float, default=[10, 12.5, 15, 20, 25])
    ap.add_argument("--end-time", type=float, default=None, help="s (default: the scene's)")
    ap.add_argument("--scene", default=SCENE)
    ap.add_argument("--out", default="results/runout-sweep")
    a = ap.parse_args()
    polydem.set_log_level("warning")
    text = open(a.scene).read()
    os.makedirs(a.out, exist_ok=True)
    results = []
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for angle in sorted(a.angles):
        run_dir = os.path.join(a.out, f"phi-{angle:g}")
        scene = polydem.parse_scene(scene_with_angle(text, angle), a.scene)
        r = polydem.run(scene, out=run_dir, end_time=a.end_time, snapshots=False)
        checks = {c["name"]: c for c in r["checks"]}
        t, d = read_series(os.path.join(run_dir, "series.csv"), "mean_displacement")
        ax.plot(t, d, label=f"{angle:g} deg")
        results.append({"friction_angle_deg": angle,
                        "mean_displacement": checks["mean displacement"]["value"],
                        "runout": checks["runout of the front"]["value"],
                        "max_displacement": checks["largest block displacement"]["value"],
                        "mean_speed_end": checks["deposit at rest"]["value"],
                        "at_rest": checks["deposit at rest"]["pass"],
                        "wall_seconds": r["wall_seconds"], "state_hash": r["state_hash"]})
        print(f"phi {angle:5g} deg: mean displacement {results[-1]['mean_displacement']:.3g} m, "
              f"runout {results[-1]['runout']:.3g} m, mean speed at the end "
              f"{results[-1]['mean_speed_end']:.3g} m/s ({'at rest' if results[-1]['at_rest'] else 'moving'}), "
              f"{r['wall_seconds']:.0f} s wall", flush=True)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("mean displacement of the free blocks [m]")
    ax.set_title("A-RUNOUT: friction sweep (cf. Keissar fig. 4.11)")
    ax.legend(title="friction angle")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "sweep.png"), dpi=110)
    falls = all(x["mean_displacement"] >= y["mean_displacement"]
                for x, y in zip(results, results[1:]))
    with open(os.path.join(a.out, "sweep.json"), "w") as f:
        json.dump({"scene": a.scene, "runs": results,
                   "displacement_falls_with_friction": falls}, f, indent=2)
    print(f"wrote {a.out}/sweep.png, sweep.json; displacement falls as friction rises: {falls}")
    return 0 if falls else 1


if __name__ == "__main__":
    sys.exit(main())

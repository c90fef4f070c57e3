#!/usr/bin/python3
"""Plots a `polydem fos` run: the mean displacement of the free blocks against time, one line per
trial (blue: stable, red: failed or still moving), as PNG. polydem fos writes the same as fos.svg
by itself; this is for reports.

    /usr/bin/python3 python_coupling/plots/plot_fos.py DIR [--out DIR/fos.png]
"""
import argparse
import csv
import json
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def plot(run_dir, out=None):
    result = json.load(open(os.path.join(run_dir, "fos.json")))
    series = {}
    with open(os.path.join(run_dir, "fos_trials.csv")) as f:
        for row in csv.DictReader(f):
            t = series.setdefault(int(row["trial"]), {"factor": float(row["factor"]),
                                                      "outcome": row["outcome"], "t": [], "d": []})
            t["t"].append(float(row["time"]))
            t["d"].append(float(row["mean_displacement"]))
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for trial in sorted(series.values(), key=lambda s: s["factor"]):
        colour = {"stable": "tab:blue", "failed": "tab:red"}.get(trial["outcome"], "tab:grey")
        ax.plot(trial["t"], trial["d"], color=colour, alpha=0.8,
                label=f"F = {trial['factor']:.4g} ({trial['outcome']})")
    limit = result["criterion"].get("displacement_limit")  # optional: none by default
    if limit is not None:
        ax.axhline(limit, color="grey", ls="--", lw=0.8)
        ax.set_ylim(0, 1.15 * limit)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("mean displacement of the free blocks [m]")
    f = result["factor_of_safety"]
    ax.set_title(f"{result['scene']}: factor of safety "
                 f"{'not bracketed' if f is None else format(f, '.4g')} (kernel {result['kernel']})")
    ax.legend(fontsize=7, ncol=2)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    out = out or os.path.join(run_dir, "fos.png")
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run_dir")
    ap.add_argument("--out")
    a = ap.parse_args()
    print(plot(a.run_dir, a.out))


if __name__ == "__main__":
    main()

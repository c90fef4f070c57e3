#!/usr/bin/python3
"""Plot the deposit of a runout (DIR/thickness.csv, as `polydem runout` writes it) to a PNG: the
thickness of the failed mass above the ground on the horizontal grid, seen from above, with the
runout figures of DIR/runout.json in the title when it exists.

    /usr/bin/python3 python_coupling/plots/plot_thickness.py DIR [--out DIR/thickness.png]
"""
import argparse
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir")
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    path = os.path.join(a.dir, "thickness.csv")
    try:
        with open(path) as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        sys.exit(f"plot_thickness: {path}: {e.strerror}")
    if not rows:
        sys.exit(f"plot_thickness: {path}: no cell")
    i = np.array([int(r["i"]) for r in rows])
    j = np.array([int(r["j"]) for r in rows])
    x = np.array([float(r["x"]) for r in rows])
    y = np.array([float(r["y"]) for r in rows])
    t = np.array([float(r["thickness"]) for r in rows])
    h = (x.max() - x.min()) / max(i.max() - i.min(), 1) if i.max() > i.min() else None
    if h is None:
        h = (y.max() - y.min()) / max(j.max() - j.min(), 1) if j.max() > j.min() else 1.0
    grid = np.full((j.max() + 1, i.max() + 1), np.nan)
    grid[j, i] = t
    x0 = x[0] - (i[0] + 0.5) * h
    y0 = y[0] - (j[0] + 0.5) * h
    extent = [x0, x0 + grid.shape[1] * h, y0, y0 + grid.shape[0] * h]
    fig, ax = plt.subplots(figsize=(8, 5))
    im = ax.imshow(np.ma.masked_invalid(grid), origin="lower", extent=extent, cmap="viridis",
                   aspect="equal", interpolation="nearest")
    fig.colorbar(im, ax=ax, label="deposit thickness [m]")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    title = "deposit thickness"
    info = os.path.join(a.dir, "runout.json")
    if os.path.exists(info):
        with open(info) as f:
            r = json.load(f)
        d = r["deposit"]
        title = (f"runout {r['runout_distance']:.3g} m, largest travel "
                 f"{r['largest_block_travel']:.3g} m; deposit {d['length']:.3g} x "
                 f"{d['width']:.3g} m" + ("" if r["at_rest"] else " (NOT at rest)"))
    ax.set_title(title, fontsize=10)
    fig.tight_layout()
    out = a.out or os.path.join(a.dir, "thickness.png")
    fig.savefig(out, dpi=120)


if __name__ == "__main__":
    main()

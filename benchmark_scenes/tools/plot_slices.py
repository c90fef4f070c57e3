#!/usr/bin/python3
"""Draws runs of A-SLICES-2D (benchmark_scenes/A-SLICES-2D.toml) side by side: each run's section
(the blocks' faces in the plane y = 0) at its first and last snapshot, the blocks of the last one
coloured by how far they moved, the first in grey outline.

    /usr/bin/python3 benchmark_scenes/tools/plot_slices.py --out FILE.png RUN_DIR[@TIME]=TITLE ...

RUN_DIR is a `polydem run` output folder with snapshots (snapshots/snapshot_*.h5); @TIME (s)
draws the snapshot nearest that time instead of the last.
"""
import argparse
import glob
import os

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402
import numpy as np  # noqa: E402


def section(path):
    """The blocks' southern faces (in y = 0, outward normal -y) as (x, z) polygons, with each
    face's displacement and fixed flag. The side walls' faces in y = 0 face +y: left out."""
    with h5py.File(path, "r") as h:
        pts = h["mesh/points"][:]
        top = h["mesh/topology"][:]
        disp = h["faces/displacement"][:]
        fixed = h["faces/fixed"][:]
    polys, d, fx = [], [], []
    i, face = 0, 0
    while i < len(top):
        n = int(top[i + 1])
        p = pts[top[i + 2:i + 2 + n]]
        normal_y = np.cross(p[1] - p[0], p[2] - p[0])[1]  # vertices counter-clockwise
        if np.all(np.abs(p[:, 1]) < 1e-2) and normal_y < 0:
            polys.append(p[:, [0, 2]])
            d.append(np.linalg.norm(disp[face]) if disp.ndim > 1 else abs(disp[face]))
            fx.append(bool(fixed[face]))
        i += 2 + n
        face += 1
    return polys, np.array(d), np.array(fx)


def snapshot_time(path):
    with h5py.File(path, "r") as h:
        return float(h.attrs["time"])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("runs", nargs="+", metavar="RUN_DIR[@TIME]=TITLE")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    fig, axes = plt.subplots(len(a.runs), 1, figsize=(8, 3.4 * len(a.runs)), squeeze=False,
                             layout="constrained")
    for ax, spec in zip(axes[:, 0], a.runs):
        folder, title = spec.split("=", 1)
        folder, _, when = folder.partition("@")
        snaps = sorted(glob.glob(os.path.join(folder, "snapshots", "snapshot_*.h5")))
        first, _, _ = section(snaps[0])
        shown = snaps[-1]
        if when:
            shown = min(snaps, key=lambda f: abs(snapshot_time(f) - float(when)))
        polys, d, fixed = section(shown)
        ax.add_collection(PolyCollection([p for p, f in zip(polys, fixed) if f],
                                         facecolor="0.85", edgecolor="0.6", linewidth=0.5))
        free = [p for p, f in zip(polys, fixed) if not f]
        coll = PolyCollection(free, array=d[~fixed], cmap="viridis", edgecolor="k",
                              linewidth=0.5)
        ax.add_collection(coll)
        ax.add_collection(PolyCollection(first, facecolor="none", edgecolor="0.4",
                                         linewidth=0.4, linestyle="--"))
        ax.set_title(f"{title} (t = {snapshot_time(shown):.1f} s)")
        ax.set_xlim(-100, 70)
        ax.set_ylim(-25, 85)
        ax.set_aspect("equal")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("z (m)")
        fig.colorbar(coll, ax=ax, label="displacement (m)", shrink=0.9)
    tmp = a.out + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, a.out)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Render a run's HDF5 snapshots (RUN_DIR/snapshots/snapshot_S.h5) to one PNG without ParaView.

A few frames (default 4: the first snapshot, two between, the last) side by side, each showing
every block's faces in 3D, the free blocks coloured by speed on one colour scale for all frames
(colour bar in m/s), fixed bodies (slopes, floors) in grey, the time above each frame. Drawn
offscreen with matplotlib's Agg backend (Poly3DCollection) from Debian's /usr/bin/python3 with
numpy and h5py; no display is needed.

    /usr/bin/python3 python_coupling/plots/render_frames.py RUN_DIR [--frames 4] [--out f.png]
                     [--elevation 22] [--azimuth -70]

Writes RUN_DIR/frames.png by default and prints its path. `polydem run ... --picture` and
`[output] picture = true` call this after the run; scripts/main-job always does. Snapshots
written with snapshot_format = "vtk" are not read: the script says so and exits with status 2.
"""
import argparse
import glob
import os
import sys

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)
from matplotlib import cm, colors  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402


class Frame:
    """One snapshot: its faces as polygons and, per face, the speed and whether it is fixed."""

    def __init__(self, path):
        with h5py.File(path, "r") as h:
            if h.attrs.get("format") not in ("polydem-snapshot", b"polydem-snapshot"):
                raise ValueError("%s is not a polydem snapshot" % path)
            self.time = float(h.attrs["time"])
            self.step = int(h.attrs["step"])
            points = h["mesh/points"][:]
            topology = h["mesh/topology"][:]
            face_count = h["particles/face_count"][:]
            speed = np.linalg.norm(h["particles/velocity"][:], axis=1)
            fixed = (h["faces/fixed"][:] != 0) if "faces/fixed" in h else None
        self.polygons = []
        i = 0
        while i < len(topology):  # XDMF Mixed: 3 (polygon), vertex count, indices
            n = int(topology[i + 1])
            self.polygons.append(points[topology[i + 2:i + 2 + n]])
            i += 2 + n
        self.speed = np.repeat(speed, face_count)
        # Without the 'fixed' field: a body that has not moved at all is taken for a fixed one.
        self.fixed = fixed if fixed is not None else np.repeat(speed == 0.0, face_count)
        self.free_points = np.concatenate(
            [p for p, f in zip(self.polygons, self.fixed) if not f] or [np.zeros((0, 3))])


def snapshot_files(run_dir):
    files = sorted(glob.glob(os.path.join(run_dir, "snapshots", "snapshot_*.h5")))
    if not files:
        vtk = glob.glob(os.path.join(run_dir, "snapshots", "*.vtp"))
        raise FileNotFoundError(
            "%s holds no HDF5 snapshots%s" % (run_dir, " (it has VTK snapshots: set [output] "
                                              "snapshot_format = \"xdmf\" to render frames)"
                                              if vtk else ""))
    return files


def pick(files, count):
    """`count` files spread evenly from the first to the last (all when there are fewer)."""
    if len(files) <= count:
        return files
    index = np.unique(np.round(np.linspace(0, len(files) - 1, count)).astype(int))
    return [files[i] for i in index]


def view_box(frames):
    """Axis limits around the free blocks of all frames (fixed bodies may reach far beyond)."""
    pts = np.concatenate([f.free_points for f in frames])
    if len(pts) == 0:
        pts = np.concatenate([np.concatenate(f.polygons) for f in frames])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    pad = 0.08 * max(hi - lo)
    return lo - pad, hi + pad


def clip_fixed(polygon, lo, hi):
    """A fixed body's face, kept when it touches the view box (big floors are cut to the box's
    footprint by clamping, which keeps their plane where they are flat and axis-aligned)."""
    if np.any(polygon.max(axis=0) < lo) or np.any(polygon.min(axis=0) > hi):
        return None
    return np.clip(polygon, lo, hi)


def render(run_dir, count=4, out=None, elevation=22.0, azimuth=-70.0):
    """Draws `count` frames of RUN_DIR's snapshots into one PNG; returns its path."""
    frames = [Frame(f) for f in pick(snapshot_files(run_dir), count)]
    lo, hi = view_box(frames)
    vmax = max(float(f.speed[~f.fixed].max()) if (~f.fixed).any() else 0.0 for f in frames)
    norm = colors.Normalize(0.0, vmax if vmax > 0 else 1.0)
    cmap = matplotlib.colormaps["viridis"]
    n = len(frames)
    ncols = 2 if n == 4 else min(n, 3)
    nrows = (n + ncols - 1) // ncols
    fig = plt.figure(figsize=(6.4 * ncols + 1.2, 5.3 * nrows))
    for k, frame in enumerate(frames):
        ax = fig.add_subplot(nrows, ncols, k + 1, projection="3d")
        polygons, face_colours, edge_colours = [], [], []
        for polygon, speed, fixed in zip(frame.polygons, frame.speed, frame.fixed):
            if fixed:
                polygon = clip_fixed(polygon, lo, hi)
                if polygon is None:
                    continue
                face_colours.append((0.78, 0.76, 0.72, 0.35))
                edge_colours.append((0.5, 0.5, 0.5, 0.25))
            else:
                face_colours.append(cmap(norm(speed)))
                edge_colours.append((0.1, 0.1, 0.1, 0.5))
            polygons.append(polygon)
        ax.add_collection3d(Poly3DCollection(polygons, facecolors=face_colours,
                                             edgecolors=edge_colours, linewidths=0.3))
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        ax.set_zlim(lo[2], hi[2])
        # True proportions (a 40 degree slope looks like one), zoomed into the panel's white space.
        ax.set_box_aspect(hi - lo, zoom=1.15)
        ax.view_init(elev=elevation, azim=azimuth)
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.set_zlabel("z [m]")
        ax.tick_params(labelsize=7)
        free_speed = frame.speed[~frame.fixed]
        ax.set_title("t = %.3g s (step %d), max speed %.3g m/s"
                     % (frame.time, frame.step, free_speed.max() if free_speed.size else 0.0),
                     fontsize=10)
    # The colour bar in a column of its own, right of the frames (not over the last one).
    fig.subplots_adjust(left=0.0, right=0.88, bottom=0.03, top=0.9, wspace=0.05, hspace=0.12)
    bar = fig.add_axes([0.9, 0.2, 0.018, 0.6])
    fig.colorbar(cm.ScalarMappable(norm=norm, cmap=cmap), cax=bar, label="speed [m/s]")
    fig.suptitle("%s: blocks coloured by speed (fixed bodies grey)"
                 % os.path.basename(os.path.abspath(run_dir)), fontsize=12)
    out = out or os.path.join(run_dir, "frames.png")
    tmp = out + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    plt.close(fig)
    os.replace(tmp, out)  # never a half-written picture under the real name
    return out


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run_dir", help="directory of a run (holds snapshots/)")
    parser.add_argument("--frames", type=int, default=4, help="number of frames (default 4)")
    parser.add_argument("--out", help="PNG to write (default: RUN_DIR/frames.png)")
    parser.add_argument("--elevation", type=float, default=22.0, help="view elevation [deg]")
    parser.add_argument("--azimuth", type=float, default=-70.0, help="view azimuth [deg]")
    args = parser.parse_args(argv)
    if args.frames < 1:
        sys.exit("render_frames: --frames must be at least 1")
    try:
        out = render(args.run_dir, args.frames, args.out, args.elevation, args.azimuth)
    except FileNotFoundError as e:
        print("render_frames: %s" % e, file=sys.stderr)
        return 2
    except (OSError, ValueError, KeyError) as e:
        sys.exit("render_frames: %s" % e)
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())

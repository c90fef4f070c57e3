#!/usr/bin/python3
"""Render a run's HDF5 snapshots (RUN_DIR/snapshots/snapshot_S.h5) to one PNG without ParaView.

A few frames (default 4: the first snapshot, two between, the last) side by side, each showing
every block's faces in 3D, fixed bodies (slopes, floors) in grey, the time above each frame. The
free blocks are coloured by one field (--field):

    speed         |velocity| [m/s], one colour scale for all frames (the default)
    displacement  |displacement since the start| [m], one colour scale for all frames
    pressure      the water pressure on each face [Pa] (snapshot field `pressure`, [water])
    joint         each face by the [[joint]] whose plane made it (the snapshot field `joint`),
                  with a legend of the joint names; faces on no joint (the mass's outer
                  surface) faint, so that the joint faces inside show through

The frames are seen from the slope's face: the camera stands on the side the free surface faces
(the area-weighted mean horizontal direction of the upward faces that lie on no joint: a rock
mass's cut face and top, a fixed slope's face), 30 deg to its left, so that an east-facing slope
is seen from the east. When the scene has no such direction (a pile on a flat floor) the view is
the fixed default azimuth -70 deg; --azimuth chooses any view. Drawn offscreen with matplotlib's
Agg backend (Poly3DCollection) from Debian's /usr/bin/python3 with numpy and h5py; no display is
needed.

    /usr/bin/python3 python_coupling/plots/render_frames.py RUN_DIR [--frames 4] [--out f.png]
                     [--field speed|displacement|pressure|joint] [--elevation 22] [--azimuth DEG]

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
from matplotlib.patches import Patch  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402


FIELDS = ("speed", "displacement", "pressure", "joint")
DEFAULT_AZIMUTH = -70.0  # deg, when the scene shows no slope face
FACE_OFFSET = -30.0  # deg: the camera stands this far to the left of the face's direction


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


class Frame:
    """One snapshot: its faces as polygons and, per face, the chosen field's value, whether the
    face's body is fixed and the [[joint]] whose plane made it (-1: none, or not written)."""

    def __init__(self, path, field="speed"):
        with h5py.File(path, "r") as h:
            if text(h.attrs.get("format")) != "polydem-snapshot":
                raise ValueError("%s is not a polydem snapshot" % path)
            self.time = float(h.attrs["time"])
            self.step = int(h.attrs["step"])
            points = h["mesh/points"][:]
            topology = h["mesh/topology"][:]
            face_count = h["particles/face_count"][:]
            speed = np.linalg.norm(h["particles/velocity"][:], axis=1)
            fixed = (h["faces/fixed"][:] != 0) if "faces/fixed" in h else None
            self.joint = h["faces/joint"][:] if "faces/joint" in h else None
            names = text(h.attrs.get("joint_names", ""))
            self.joint_names = names.split("\n") if names else []
            if field == "displacement":
                if "faces/displacement" not in h:
                    raise KeyError("%s has no field 'displacement' (add it to [output] fields)"
                                   % path)
                self.value = np.linalg.norm(h["faces/displacement"][:], axis=1)
            elif field == "pressure":
                if "faces/pressure" not in h:
                    raise KeyError("%s has no field 'pressure' (add it to [output] fields)" % path)
                self.value = h["faces/pressure"][:]
            elif field == "joint" and self.joint is None:
                raise KeyError("%s has no field 'joint' (add it to [output] fields)" % path)
        self.polygons = []
        i = 0
        while i < len(topology):  # XDMF Mixed: 3 (polygon), vertex count, indices
            n = int(topology[i + 1])
            self.polygons.append(points[topology[i + 2:i + 2 + n]])
            i += 2 + n
        if field == "speed":
            self.value = np.repeat(speed, face_count)
        elif field == "joint":
            self.value = self.joint.astype(float)
        if self.joint is None:
            self.joint = np.full(len(self.polygons), -1)
        # Without the 'fixed' field: a body that has not moved at all is taken for a fixed one.
        self.fixed = fixed if fixed is not None else np.repeat(speed == 0.0, face_count)
        self.free_points = np.concatenate(
            [p for p, f in zip(self.polygons, self.fixed) if not f] or [np.zeros((0, 3))])


def area_vector(polygon):
    """Area times outward unit normal of a planar polygon, counter-clockwise seen from outside
    (Newell's formula)."""
    return 0.5 * np.cross(polygon, np.roll(polygon, -1, axis=0)).sum(axis=0)


def face_direction(frame, lo, hi):
    """The horizontal unit vector the slope's face looks towards, or None.

    The sum of the area vectors of the faces that face up (n_z > 1e-3) and lie on no joint: the
    cut face and top of a rock mass (joint faces are inside the mass; vertical sides of a region
    are left out), the face of a fixed slope within the view box. Horizontal faces add nothing to
    the horizontal part; it counts when it is at least 5 % of those faces' area."""
    total, area = np.zeros(3), 0.0
    for polygon, fixed, joint in zip(frame.polygons, frame.fixed, frame.joint):
        if joint >= 0 or (fixed and clip_fixed(polygon, lo, hi) is None):
            continue
        a = area_vector(polygon)
        size = np.linalg.norm(a)
        if size == 0.0 or a[2] <= 1e-3 * size:
            continue
        total += a
        area += size
    horizontal = np.array([total[0], total[1], 0.0])
    length = np.linalg.norm(horizontal)
    if area == 0.0 or length < 0.05 * area:
        return None
    return horizontal / length


def face_azimuth(frame, lo, hi):
    """matplotlib's view azimuth [deg] that looks at the slope's face (the camera on the side the
    face looks towards, FACE_OFFSET to its left), or DEFAULT_AZIMUTH."""
    d = face_direction(frame, lo, hi)
    if d is None:
        return DEFAULT_AZIMUTH
    return float(np.degrees(np.arctan2(d[1], d[0]))) + FACE_OFFSET


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


def joint_colour(joint):
    """A colour per joint id (matplotlib's tab10, then tab20); faces on no joint (the mass's
    outer surface) in a faint stone colour, so that the joint faces inside show through."""
    if joint < 0:
        return (0.86, 0.82, 0.74, 0.12)
    palette = matplotlib.colormaps["tab10" if joint < 10 else "tab20"]
    return palette(joint % palette.N)


def render(run_dir, count=4, out=None, elevation=22.0, azimuth=None, field="speed"):
    """Draws `count` frames of RUN_DIR's snapshots into one PNG, the free blocks coloured by
    `field`, seen from `azimuth` (None: from the slope's face); returns the PNG's path."""
    if field not in FIELDS:
        raise ValueError("unknown field '%s' (known: %s)" % (field, ", ".join(FIELDS)))
    frames = [Frame(f, field) for f in pick(snapshot_files(run_dir), count)]
    lo, hi = view_box(frames)
    if azimuth is None:
        azimuth = face_azimuth(frames[0], lo, hi)
    unit = {"speed": "m/s", "displacement": "m", "pressure": "Pa"}.get(field)
    if unit:
        vmax = max(float(f.value[~f.fixed].max()) if (~f.fixed).any() else 0.0 for f in frames)
        norm = colors.Normalize(0.0, vmax if vmax > 0 else 1.0)
        cmap = matplotlib.colormaps["viridis"]

    def colour(value):
        return cmap(norm(value)) if unit else joint_colour(int(value))

    n = len(frames)
    ncols = 2 if n == 4 else min(n, 3)
    nrows = (n + ncols - 1) // ncols
    fig = plt.figure(figsize=(6.4 * ncols + 1.2, 5.3 * nrows))
    for k, frame in enumerate(frames):
        ax = fig.add_subplot(nrows, ncols, k + 1, projection="3d")
        polygons, face_colours, edge_colours = [], [], []
        for polygon, value, fixed in zip(frame.polygons, frame.value, frame.fixed):
            if fixed:
                polygon = clip_fixed(polygon, lo, hi)
                if polygon is None:
                    continue
                face_colours.append((0.78, 0.76, 0.72, 0.35))
                edge_colours.append((0.5, 0.5, 0.5, 0.25))
            else:
                face_colours.append(colour(value))
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
        free = frame.value[~frame.fixed]
        on_joints = int(np.sum((frame.joint >= 0) & ~frame.fixed))
        summary = ("max %s %.3g %s" % (field, free.max() if free.size else 0.0, unit)
                   if unit else "%d faces on joints" % on_joints)
        ax.set_title("t = %.3g s (step %d), %s" % (frame.time, frame.step, summary), fontsize=10)
    # The colour bar or legend in a column of its own, right of the frames (not over the last one).
    fig.subplots_adjust(left=0.0, right=0.88 if unit else 0.8, bottom=0.03, top=0.9, wspace=0.05,
                        hspace=0.12)
    if unit:
        bar = fig.add_axes([0.9, 0.2, 0.018, 0.6])
        fig.colorbar(cm.ScalarMappable(norm=norm, cmap=cmap), cax=bar,
                     label="%s [%s]" % (field, unit))
    else:
        fig.legend(handles=joint_legend(frames), loc="center left", bbox_to_anchor=(0.81, 0.5),
                   fontsize=9, title="joint", frameon=False)
    fig.suptitle("%s: blocks coloured by %s (fixed bodies grey)"
                 % (os.path.basename(os.path.abspath(run_dir)), field), fontsize=12)
    out = out or os.path.join(run_dir, "frames.png")
    tmp = out + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    plt.close(fig)
    os.replace(tmp, out)  # never a half-written picture under the real name
    return out


def joint_legend(frames):
    """One legend entry per joint that colours a free face in some frame, named by the
    snapshot's joint_names, and one for the faces on no joint."""
    names = frames[-1].joint_names
    used = sorted(set(int(j) for f in frames for j in f.joint[~f.fixed]))
    handles = []
    for j in used:
        label = names[j] if 0 <= j < len(names) else ("no joint" if j < 0 else "joint %d" % j)
        colour = joint_colour(j)[:3] + (1.0,) if j >= 0 else (0.86, 0.82, 0.74, 0.5)
        handles.append(Patch(facecolor=colour, edgecolor=(0.1, 0.1, 0.1, 0.5), label=label))
    return handles


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("run_dir", help="directory of a run (holds snapshots/)")
    parser.add_argument("--frames", type=int, default=4, help="number of frames (default 4)")
    parser.add_argument("--out", help="PNG to write (default: RUN_DIR/frames.png)")
    parser.add_argument("--field", default="speed", choices=FIELDS,
                        help="what colours the free blocks (default speed)")
    parser.add_argument("--elevation", type=float, default=22.0, help="view elevation [deg]")
    parser.add_argument("--azimuth", type=float, default=None,
                        help="view azimuth [deg] (default: from the slope's face)")
    args = parser.parse_args(argv)
    if args.frames < 1:
        sys.exit("render_frames: --frames must be at least 1")
    try:
        out = render(args.run_dir, args.frames, args.out, args.elevation, args.azimuth, args.field)
    except FileNotFoundError as e:
        print("render_frames: %s" % e, file=sys.stderr)
        return 2
    except (OSError, ValueError, KeyError) as e:
        sys.exit("render_frames: %s" % e)
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())

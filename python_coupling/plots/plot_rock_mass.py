#!/usr/bin/python3
"""Draws the blocks of a scene as its file places them: free blocks in colour, fixed blocks as
grey glass, so that a [[rock_mass]] can be looked at before it is run.

    PYTHONPATH=build/python /usr/bin/python3 python_coupling/plots/plot_rock_mass.py \\
        benchmark_scenes/S-CUT-SLOPE-53.toml --out slope.png [--view 25 -60] [--no-fixed]

Needs the polydem package (build/python) and Debian's matplotlib.
"""
import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

import polydem  # noqa: E402


def block_faces(scene):
    """(faces, fixed, centroid) of every particle, faces as lists of (k, 3) corner arrays."""
    shapes, parts = scene.shapes, scene.particles
    out = []
    for i in range(scene.num_particles):
        q = parts["orientation"][i]
        w, x, y, z = q
        rot = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
        v = shapes[parts["shape"][i]]["vertices"] @ rot.T + parts["position"][i]
        p = polydem.ConvexPolyhedron(v)
        out.append(([p.vertices[f] for f in p.faces], bool(parts["fixed"][i]), p.centroid))
    return out


def plot(scene_file, out, view=(25.0, -60.0), fixed=True, title=None):
    scene = polydem.read_scene(scene_file)
    blocks = block_faces(scene)
    fig = plt.figure(figsize=(8, 6))
    ax = fig.add_subplot(111, projection="3d")
    rng = np.random.default_rng(7)
    corners = []
    for faces, is_fixed, _ in blocks:
        if is_fixed and not fixed:
            continue
        colour = (0.6, 0.6, 0.6, 0.08) if is_fixed else (*rng.uniform(0.35, 0.95, 3), 1.0)
        edge = (0.2, 0.2, 0.2, 0.25 if is_fixed else 0.8)
        ax.add_collection3d(Poly3DCollection(faces, facecolor=colour, edgecolor=edge,
                                             linewidth=0.3 if is_fixed else 0.5))
        corners.extend(faces)
    pts = np.vstack(corners)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    centre, half = 0.5 * (lo + hi), 0.5 * (hi - lo).max()
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)
    ax.set_xlabel("x (east) [m]")
    ax.set_ylabel("y (north) [m]")
    ax.set_zlabel("z [m]")
    ax.view_init(*view)
    free = sum(1 for b in blocks if not b[1])
    ax.set_title(title or f"{scene.id}: {free} free blocks (colour), "
                 f"{len(blocks) - free} fixed (grey)")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scene")
    ap.add_argument("--out", required=True, help="PNG to write")
    ap.add_argument("--view", nargs=2, type=float, default=(25.0, -60.0),
                    metavar=("ELEVATION", "AZIMUTH"))
    ap.add_argument("--no-fixed", action="store_true", help="leave the fixed blocks out")
    ap.add_argument("--title")
    a = ap.parse_args()
    polydem.set_log_level("warning")
    print(plot(a.scene, a.out, tuple(a.view), not a.no_fixed, a.title))


if __name__ == "__main__":
    main()

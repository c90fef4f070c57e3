#!/usr/bin/env python3
"""F-TOPPLING-SET (BENCHMARKS.md section F): `polydem fos` with its default criterion on Goodman
and Bray's toppling set (benchmark_scenes/F-TOPPLING-SET.toml) gives the limit friction angle of
their recursion within 2 deg. The recursion's inputs are read back from the scene file: the
columns' boxes give dx and the heights, their rotation the dip psi_p of their bases, their
positions the level of each base (the steps), the material the friction angle.

usage: fos_toppling_set_test.py POLYDEM SCENE WORKDIR"""
import json
import math
import os
import shutil
import sys
import tomllib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import goodman_bray  # noqa: E402
from scene_test_util import expect, run, FAILURES  # noqa: E402


def columns(scene):
    """psi_p (deg), dx, and the heights and base levels of the columns from the toe up."""
    shapes = {s["name"]: s for s in scene["shape"]}
    free = [p for p in scene["particle"] if not p.get("fixed", False)]
    boxes = [shapes[p["shape"]] for p in free]
    psi = boxes[0]["rotation"]["angle"]
    for b in boxes:
        assert b["type"] == "box" and b["rotation"]["axis"] == [0, 1, 0], b
        assert b["rotation"]["angle"] == psi and b["size"][0] == boxes[0]["size"][0], b
    s, c = math.sin(math.radians(psi)), math.cos(math.radians(psi))
    down = (c, 0.0, -s)  # down the bases
    normal = (s, 0.0, c)  # their normal
    dot = lambda u, v: sum(a * b for a, b in zip(u, v))
    rows = []
    for p, b in zip(free, boxes):
        h = b["size"][2]
        rows.append((dot(p["position"], down), h, dot(p["position"], normal) - 0.5 * h))
    rows.sort(key=lambda r: -r[0])  # the toe is the farthest down
    return psi, boxes[0]["size"][0], [r[1] for r in rows], [r[2] for r in rows]


def main():
    polydem, scene_path, workdir = (os.path.abspath(a) for a in sys.argv[1:4])
    shutil.rmtree(workdir, ignore_errors=True)
    os.makedirs(workdir)
    with open(scene_path, "rb") as f:
        scene = tomllib.load(f)
    psi, dx, heights, bases = columns(scene)
    phi = float(scene["material"][0]["friction_angle"])
    phi_star, modes = goodman_bray.limit_friction(psi, dx, heights, bases)
    print(f"Goodman and Bray: psi_p {psi} deg, dx {dx} m, heights {heights}, bases "
          f"{[round(z, 6) for z in bases]}: limit friction {phi_star:.3f} deg, just below it {modes}")
    run([polydem, "fos", scene_path, "--out", "fos"], workdir)
    with open(os.path.join(workdir, "fos", "fos.json")) as f:
        j = json.load(f)
    factor = j["factor_of_safety"]
    expect(factor is not None, f"no factor of safety: {j['note']}")
    if factor is not None:
        phi_fos = math.degrees(math.atan(math.tan(math.radians(phi)) / factor))
        print(f"polydem fos: F = {factor:.4f}, limit friction {phi_fos:.3f} deg "
              f"(Goodman and Bray {phi_star:.3f} deg, difference {phi_fos - phi_star:+.2f} deg)")
        expect(abs(phi_fos - phi_star) <= 2.0,
               f"limit friction {phi_fos:.2f} deg, Goodman and Bray {phi_star:.2f} deg")
    c = j["criterion"]
    expect(c["local_damping_from"].startswith("default"), f"not the default criterion: {c}")
    # Every stable trial says how far it moved, within the criterion's share of a block's size.
    for t in j["trials"]:
        if t["outcome"] == "stable":
            expect(0.0 <= t["max_reach_fraction"] <= c["moved_fraction"],
                   f"stable trial at F = {t['factor']} moved {t['max_reach_fraction']} of a block")
    m = j["mechanism"]
    expect(m is not None and "toppling" in m["summary"],
           f"mechanism: {m and m['summary']} (Goodman and Bray: {modes})")
    for name in ("frames.png", "blocks.csv"):
        expect(os.path.isfile(os.path.join(workdir, "fos", "mechanism", name)), f"no mechanism/{name}")
    if FAILURES:
        sys.exit(f"{len(FAILURES)} check(s) failed")
    print("all checks passed")


if __name__ == "__main__":
    main()
